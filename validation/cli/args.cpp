#include "validation/cli/args.h"

#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>

#include "pbd/io/number_text.h"
#include "pbd/io/suggestion.h"
#include "validation/run/overrides.h"

namespace pbdval::cli {

std::string ParsedArgs::value(const std::string& name, const std::string& fallback) const {
  const auto it = options.find(name);
  return it == options.end() || it->second.empty() ? fallback : it->second.back();
}

const std::vector<std::string>& ParsedArgs::values(const std::string& name) const {
  static const std::vector<std::string> none;
  const auto it = options.find(name);
  return it == options.end() ? none : it->second;
}

double ParsedArgs::number(const std::string& name, double fallback) const {
  if (!options.count(name)) return fallback;
  const std::string text = value(name);
  const std::optional<double> v = pbd::parseReal(text);
  if (!v) throw UsageError("--" + name + ": expected a number, got '" + text + "'");
  return *v;
}

long ParsedArgs::integer(const std::string& name, long fallback) const {
  if (!options.count(name)) return fallback;
  const std::string text = value(name);
  const std::optional<std::int64_t> v = pbd::parseInteger(text);
  if (!v) throw UsageError("--" + name + ": expected an integer, got '" + text + "'");
  return static_cast<long>(*v);
}

std::int64_t ParsedArgs::integerIn(const std::string& name, std::int64_t fallback,
                                   std::int64_t minimum, std::int64_t maximum) const {
  if (!options.count(name)) return fallback;
  const std::string text = value(name);
  const std::optional<std::int64_t> v = pbd::parseInteger(text);
  if (!v || *v < minimum || *v > maximum)
    throw UsageError("--" + name + ": expected an integer from " + std::to_string(minimum) +
                     " to " + std::to_string(maximum) + ", got '" + text + "'");
  return *v;
}

std::vector<std::string> ParsedArgs::list(const std::string& name) const {
  std::vector<std::string> items;
  std::stringstream in(value(name));
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) continue;
    for (const std::string& earlier : items)
      if (earlier == item)
        throw UsageError("--" + name + ": '" + item +
                         "' is listed twice (each would make the same runs again)");
    items.push_back(item);
  }
  return items;
}

ArgParser::ArgParser(std::string command, std::string synopsis, std::string description)
    : command_(std::move(command)),
      synopsis_(std::move(synopsis)),
      description_(std::move(description)) {}

ArgParser& ArgParser::option(const std::string& name, const std::string& valueName,
                             const std::string& help, bool repeatable) {
  options_.push_back({name, valueName, help, repeatable, false});
  return *this;
}

ArgParser& ArgParser::flag(const std::string& name, const std::string& help) {
  options_.push_back({name, "", help, false, true});
  return *this;
}

ArgParser& ArgParser::positionals(const std::string& name, const std::string& help, int minimum,
                                  int maximum) {
  positionalName_ = name;
  positionalHelp_ = help;
  minimumPositionals_ = minimum;
  maximumPositionals_ = maximum;
  return *this;
}

ArgParser& ArgParser::epilog(const std::string& text) {
  epilog_ = text;
  return *this;
}

const ArgParser::Option* ArgParser::find(const std::string& name) const {
  for (const Option& o : options_)
    if (o.name == name) return &o;
  return nullptr;
}

ParsedArgs ArgParser::parse(const std::vector<std::string>& args) const {
  ParsedArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "-h" || arg == "--help") {
      parsed.helpRequested = true;
      return parsed;
    }
    if (arg.size() > 2 && arg.compare(0, 2, "--") == 0) {
      std::string name = arg.substr(2), inlineValue;
      const bool hasInline = name.find('=') != std::string::npos;
      if (hasInline) {
        inlineValue = name.substr(name.find('=') + 1);
        name = name.substr(0, name.find('='));
      }
      const Option* option = find(name);
      if (!option) {
        std::vector<std::string> known;
        for (const Option& o : options_)
          known.push_back("--" + o.name);
        throw UsageError("unknown option '--" + name + "'" + pbd::didYouMean("--" + name, known));
      }
      if (option->isFlag) {
        if (hasInline) throw UsageError("--" + name + " takes no value");
        parsed.flags.insert(name);
        continue;
      }
      std::string value;
      if (hasInline) {
        value = inlineValue;
      } else {
        if (i + 1 >= args.size())
          throw UsageError("--" + name + " needs a value (" + option->valueName + ")");
        value = args[++i];
      }
      auto& slot = parsed.options[name];
      if (!slot.empty() && !option->repeatable)
        throw UsageError("--" + name + " given more than once");
      slot.push_back(value);
      continue;
    }
    parsed.positionals.push_back(arg);
  }
  const int count = static_cast<int>(parsed.positionals.size());
  if (count < minimumPositionals_)
    throw UsageError("missing " +
                     (positionalName_.empty() ? std::string("argument") : positionalName_));
  if (maximumPositionals_ >= 0 && count > maximumPositionals_)
    throw UsageError("unexpected argument '" +
                     parsed.positionals[static_cast<std::size_t>(maximumPositionals_)] + "'");
  return parsed;
}

std::optional<int> ArgParser::parseOrExit(const std::vector<std::string>& arguments,
                                          ParsedArgs& args) const {
  try {
    args = parse(arguments);
  } catch (const UsageError& e) {
    return usageError(e.what());
  }
  if (args.helpRequested) {
    std::fputs(help().c_str(), stdout);
    return 0;
  }
  return std::nullopt;
}

int ArgParser::usageError(const std::string& message) const {
  std::fprintf(stderr, "pbdval %s: %s (see 'pbdval %s --help')\n", command_.c_str(),
               message.c_str(), command_.c_str());
  return 2;
}

int ArgParser::inputError(const std::string& message) const {
  std::fprintf(stderr, "pbdval %s: error: %s\n", command_.c_str(), message.c_str());
  return 2;
}

int ArgParser::exitForCurrentException() const {
  try {
    throw;
  } catch (const UsageError& e) {
    return usageError(e.what());
  } catch (const OptionError& e) {
    return usageError(e.what());
  } catch (const std::exception& e) {
    return inputError(e.what());
  } catch (...) {
    return inputError("an unknown failure");
  }
}

std::string ArgParser::help() const {
  std::ostringstream out;
  out << "usage: pbdval " << command_ << ' ' << synopsis_ << "\n\n" << description_ << "\n";
  if (!positionalName_.empty())
    out << "\n  " << positionalName_ << "\n      " << positionalHelp_ << "\n";
  if (!options_.empty()) {
    out << "\noptions:\n";
    for (const Option& o : options_) {
      out << "  --" << o.name;
      if (!o.isFlag) out << ' ' << o.valueName;
      out << "\n      " << o.help;
      if (o.repeatable) out << " (repeatable)";
      out << "\n";
    }
  }
  out << "  -h, --help\n      show this help\n";
  if (!epilog_.empty()) out << "\n" << epilog_ << "\n";
  return out.str();
}

}  // namespace pbdval::cli
