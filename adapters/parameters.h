// Typed method parameters: declared once per method (kind, default, bounds, unit), and parsed,
// range-checked and formatted here for every engine, built-in or external. Engines read the
// checked values back through Method (engine.h); none parses text itself.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace pbdval {

enum class ParameterKind {
  Real,      ///< a finite number within [minimum, maximum]
  Integer,   ///< a whole number within [minimum, maximum]
  Bool,      ///< true/false (also 1/0)
  Choice,    ///< one of `choices`
  Duration,  ///< seconds ("0.01"), or a multiple of the scene's step ("4h"); at least
             ///< `minimumSteps` steps and within [minimum, maximum] seconds
};
const char* parameterKindName(ParameterKind kind);

/// A parameter's value as checked against its declaration.
struct ParameterValue {
  ParameterKind kind = ParameterKind::Real;
  double number = 0;     ///< Real, Integer, Bool (0/1), Duration (seconds, or steps if inSteps)
  bool inSteps = false;  ///< Duration only: `number` counts steps
  std::string choice;    ///< Choice only

  /// The canonical text: "0.2", "10", "true", "Newton", "4h".
  std::string text() const;
  bool operator==(const ParameterValue& other) const;
};

struct ParameterSpec {
  std::string name;
  ParameterKind kind = ParameterKind::Real;
  std::string defaultValue;  ///< as text; a test checks every default parses
  double minimum = -std::numeric_limits<double>::infinity();
  double maximum = std::numeric_limits<double>::infinity();
  bool minimumExclusive = false;  ///< (minimum, ...] instead of [minimum, ...]
  bool maximumExclusive = false;
  std::vector<std::string> choices;  ///< Choice only
  double minimumSteps = 0;           ///< Duration only: at least this many scene steps
  std::string unit;                  ///< "s", "m", "m/s", "" for pure numbers
  std::string description;

  /// "an integer in [1, 100]", "a number in (0, 2)", "one of Newton, CG, PGS", ...
  std::string expectation() const;
};

/// Builders for the common declarations.
ParameterSpec realParameter(std::string name, double defaultValue, double minimum, double maximum,
                            std::string unit, std::string description);
ParameterSpec integerParameter(std::string name, std::int64_t defaultValue, double minimum,
                               double maximum, std::string description);
ParameterSpec boolParameter(std::string name, bool defaultValue, std::string description);
ParameterSpec choiceParameter(std::string name, std::string defaultValue,
                              std::vector<std::string> choices, std::string description);
ParameterSpec durationParameter(std::string name, std::string defaultValue, double minimumSteps,
                                std::string description);

/// Parses and checks `text` against `spec`. Throws std::invalid_argument
/// "method M: NAME: expected <expectation>, got 'TEXT'".
ParameterValue parseParameter(const ParameterSpec& spec, const std::string& text,
                              const std::string& method);

/// A Duration value in seconds at the scene step `stepSize`, checked against the declaration's
/// minimum in steps and bounds in seconds (a time given in seconds is checked against the
/// step here, once the step is known). Throws std::invalid_argument like parseParameter.
double durationSeconds(const ParameterSpec& spec, const ParameterValue& value, double stepSize,
                       const std::string& method);

/// Checks an already typed value (from a catalogue or results file) against `spec`.
void checkParameter(const ParameterSpec& spec, const ParameterValue& value,
                    const std::string& method);

}  // namespace pbdval
