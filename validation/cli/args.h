// A small command-line parser for the pbdval subcommands: `--name value`, `--name=value`,
// flags, repeatable options, positionals, and generated --help text.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbdval::cli {

/// Bad usage: the message is printed with a pointer to --help; exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ParsedArgs {
  std::map<std::string, std::vector<std::string>> options;
  std::set<std::string> flags;
  std::vector<std::string> positionals;
  bool helpRequested = false;

  bool has(const std::string& name) const { return options.count(name) || flags.count(name); }
  std::string value(const std::string& name, const std::string& fallback = "") const;
  const std::vector<std::string>& values(const std::string& name) const;
  /// A number option; throws UsageError naming the option when it is not a finite number.
  double number(const std::string& name, double fallback) const;
  long integer(const std::string& name, long fallback) const;
  /// An integer option in [minimum, maximum], read without wrap-around; throws UsageError
  /// "--NAME: expected an integer from MIN to MAX, got 'TEXT'".
  std::int64_t integerIn(const std::string& name, std::int64_t fallback, std::int64_t minimum,
                         std::int64_t maximum) const;
  /// A comma-separated list option ("pbd,ode"); throws UsageError when an item is listed twice
  /// (a repeated engine or method would make the same runs twice).
  std::vector<std::string> list(const std::string& name) const;
};

class ArgParser {
 public:
  ArgParser(std::string command, std::string synopsis, std::string description);
  ArgParser& option(const std::string& name, const std::string& valueName, const std::string& help,
                    bool repeatable = false);
  ArgParser& flag(const std::string& name, const std::string& help);
  ArgParser& positionals(const std::string& name, const std::string& help, int minimum,
                         int maximum /* -1: unlimited */);
  /// Appended to --help (examples, notes).
  ArgParser& epilog(const std::string& text);

  ParsedArgs parse(const std::vector<std::string>& args) const;
  std::string help() const;
  const std::string& command() const { return command_; }

  /// Parses `arguments` into `args`. Returns the exit code when the command should stop here:
  /// 0 after printing --help, 2 after printing a usage error; std::nullopt to go on.
  std::optional<int> parseOrExit(const std::vector<std::string>& arguments, ParsedArgs& args) const;
  /// Prints "pbdval COMMAND: message (see 'pbdval COMMAND --help')" and returns 2.
  int usageError(const std::string& message) const;
  /// Prints "pbdval COMMAND: error: message" and returns 2 (unreadable input).
  int inputError(const std::string& message) const;
  /// The exit for the exception being handled; call it in a `catch (...)` block: a UsageError
  /// or an OptionError (a bad option value) is a usage error, any other exception an input
  /// error.
  int exitForCurrentException() const;

 private:
  struct Option {
    std::string name, valueName, help;
    bool repeatable = false;
    bool isFlag = false;
  };
  const Option* find(const std::string& name) const;

  std::string command_, synopsis_, description_, epilog_;
  std::vector<Option> options_;
  std::string positionalName_, positionalHelp_;
  int minimumPositionals_ = 0, maximumPositionals_ = 0;
};

}  // namespace pbdval::cli
