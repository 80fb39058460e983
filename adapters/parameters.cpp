#include "adapters/parameters.h"

#include <cmath>
#include <stdexcept>

#include "pbd/io/number_text.h"

namespace pbdval {
namespace {

std::string bound(double value) {
  return pbd::formatReal(value);
}

std::string interval(const ParameterSpec& s) {
  const bool low = std::isfinite(s.minimum), high = std::isfinite(s.maximum);
  if (low && high)
    return std::string("in ") + (s.minimumExclusive ? "(" : "[") + bound(s.minimum) + ", " +
           bound(s.maximum) + (s.maximumExclusive ? ")" : "]");
  if (low) return std::string(s.minimumExclusive ? "> " : ">= ") + bound(s.minimum);
  if (high) return std::string(s.maximumExclusive ? "< " : "<= ") + bound(s.maximum);
  return "";
}

bool withinBounds(const ParameterSpec& s, double v) {
  if (s.minimumExclusive ? !(v > s.minimum) : !(v >= s.minimum)) return false;
  if (s.maximumExclusive ? !(v < s.maximum) : !(v <= s.maximum)) return false;
  return true;
}

[[noreturn]] void reject(const ParameterSpec& spec, const std::string& text,
                         const std::string& method) {
  throw std::invalid_argument("method " + method + ": " + spec.name + ": expected " +
                              spec.expectation() + ", got '" + text + "'");
}

}  // namespace

const char* parameterKindName(ParameterKind kind) {
  switch (kind) {
    case ParameterKind::Real:
      return "real";
    case ParameterKind::Integer:
      return "integer";
    case ParameterKind::Bool:
      return "bool";
    case ParameterKind::Choice:
      return "choice";
    case ParameterKind::Duration:
      return "duration";
  }
  return "?";
}

std::string ParameterValue::text() const {
  switch (kind) {
    case ParameterKind::Real:
      return pbd::formatReal(number);
    case ParameterKind::Integer:
      return std::to_string(static_cast<std::int64_t>(number));
    case ParameterKind::Bool:
      return number != 0 ? "true" : "false";
    case ParameterKind::Choice:
      return choice;
    case ParameterKind::Duration:
      return pbd::formatReal(number) + (inSteps ? "h" : "");
  }
  return "";
}

bool ParameterValue::operator==(const ParameterValue& other) const {
  return kind == other.kind && number == other.number && inSteps == other.inSteps &&
         choice == other.choice;
}

std::string ParameterSpec::expectation() const {
  const std::string range = interval(*this);
  switch (kind) {
    case ParameterKind::Real:
      return "a number" + (range.empty() ? "" : " " + range);
    case ParameterKind::Integer:
      return "an integer" + (range.empty() ? "" : " " + range);
    case ParameterKind::Bool:
      return "true or false (or 1 or 0)";
    case ParameterKind::Choice: {
      std::string list;
      for (const std::string& c : choices)
        list += (list.empty() ? "" : ", ") + c;
      return "one of " + list;
    }
    case ParameterKind::Duration: {
      std::string text = "a time in seconds or a multiple of the step ('4h')";
      if (minimumSteps > 0) text += ", at least " + bound(minimumSteps) + "h";
      if (!range.empty()) text += ", seconds " + range;
      return text;
    }
  }
  return "";
}

ParameterSpec realParameter(std::string name, double defaultValue, double minimum, double maximum,
                            std::string unit, std::string description) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = ParameterKind::Real;
  s.defaultValue = pbd::formatReal(defaultValue);
  s.minimum = minimum;
  s.maximum = maximum;
  s.unit = std::move(unit);
  s.description = std::move(description);
  return s;
}

ParameterSpec integerParameter(std::string name, std::int64_t defaultValue, double minimum,
                               double maximum, std::string description) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = ParameterKind::Integer;
  s.defaultValue = std::to_string(defaultValue);
  s.minimum = minimum;
  s.maximum = maximum;
  s.description = std::move(description);
  return s;
}

ParameterSpec boolParameter(std::string name, bool defaultValue, std::string description) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = ParameterKind::Bool;
  s.defaultValue = defaultValue ? "true" : "false";
  s.description = std::move(description);
  return s;
}

ParameterSpec choiceParameter(std::string name, std::string defaultValue,
                              std::vector<std::string> choices, std::string description) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = ParameterKind::Choice;
  s.defaultValue = std::move(defaultValue);
  s.choices = std::move(choices);
  s.description = std::move(description);
  return s;
}

ParameterSpec durationParameter(std::string name, std::string defaultValue, double minimumSteps,
                                std::string description) {
  ParameterSpec s;
  s.name = std::move(name);
  s.kind = ParameterKind::Duration;
  s.defaultValue = std::move(defaultValue);
  s.minimum = 0;
  s.minimumExclusive = true;
  s.minimumSteps = minimumSteps;
  s.unit = "s";
  s.description = std::move(description);
  return s;
}

ParameterValue parseParameter(const ParameterSpec& spec, const std::string& text,
                              const std::string& method) {
  ParameterValue value;
  value.kind = spec.kind;
  switch (spec.kind) {
    case ParameterKind::Real: {
      const auto v = pbd::parseReal(text);
      if (!v) reject(spec, text, method);
      value.number = *v;
      break;
    }
    case ParameterKind::Integer: {
      const auto v = pbd::parseInteger(text);
      if (!v) reject(spec, text, method);
      value.number = double(*v);
      break;
    }
    case ParameterKind::Bool:
      if (text == "true" || text == "1")
        value.number = 1;
      else if (text == "false" || text == "0")
        value.number = 0;
      else
        reject(spec, text, method);
      break;
    case ParameterKind::Choice:
      value.choice = text;
      break;
    case ParameterKind::Duration: {
      value.inSteps = !text.empty() && text.back() == 'h';
      const auto v = pbd::parseReal(value.inSteps ? text.substr(0, text.size() - 1) : text);
      if (!v) reject(spec, text, method);
      value.number = *v;
      break;
    }
  }
  try {
    checkParameter(spec, value, method);
  } catch (const std::invalid_argument&) {
    reject(spec, text, method);
  }
  return value;
}

double durationSeconds(const ParameterSpec& spec, const ParameterValue& value, double stepSize,
                       const std::string& method) {
  checkParameter(spec, value, method);
  const double seconds = value.inSteps ? value.number * stepSize : value.number;
  const bool enoughSteps = seconds >= spec.minimumSteps * stepSize * (1 - 1e-12);
  if (!enoughSteps || !withinBounds(spec, seconds))
    throw std::invalid_argument("method " + method + ": " + spec.name + ": expected " +
                                spec.expectation() + " (" + pbd::formatReal(spec.minimumSteps) +
                                "h = " + pbd::formatReal(spec.minimumSteps * stepSize) +
                                " s at this scene's step), got '" + value.text() + "'");
  return seconds;
}

void checkParameter(const ParameterSpec& spec, const ParameterValue& value,
                    const std::string& method) {
  const auto fail = [&] { reject(spec, value.text(), method); };
  if (value.kind != spec.kind) fail();
  switch (spec.kind) {
    case ParameterKind::Real:
    case ParameterKind::Integer:
      if (!std::isfinite(value.number) || !withinBounds(spec, value.number)) fail();
      if (spec.kind == ParameterKind::Integer && value.number != std::floor(value.number)) fail();
      break;
    case ParameterKind::Bool:
      if (value.number != 0 && value.number != 1) fail();
      break;
    case ParameterKind::Choice: {
      bool known = false;
      for (const std::string& c : spec.choices)
        known = known || c == value.choice;
      if (!known) fail();
      break;
    }
    case ParameterKind::Duration:
      // Seconds are checked against the bounds here; steps against minimumSteps here and, once
      // the step is known, against the bounds in Method::seconds.
      if (!std::isfinite(value.number) || !(value.number > 0)) fail();
      if (value.inSteps && value.number < spec.minimumSteps * (1 - 1e-12)) fail();
      if (!value.inSteps && !withinBounds(spec, value.number)) fail();
      break;
  }
}

}  // namespace pbdval
