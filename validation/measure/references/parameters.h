// The `parameters` object of an analytic reference (Validation.reference.parameters), read
// with errors that name the model, the parameter and what was expected:
//   analytic reference 'pendulum': parameter 'pivot': expected an array of 3 numbers
// Unknown keys are errors (they are most likely misspelled).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pbd/math/types.h"

namespace pbdval {

class ReferenceParameters {
 public:
  /// Parses `jsonText` (an object) for model `model`, accepting only the keys in `known`.
  ReferenceParameters(std::string model, const std::string& jsonText,
                      const std::vector<std::string>& known);

  const std::string& model() const { return model_; }
  bool has(const std::string& key) const { return json_.contains(key); }

  std::optional<double> number(const std::string& key) const;
  /// A number > 0.
  std::optional<double> positiveNumber(const std::string& key) const;
  /// A number ≥ 0.
  std::optional<double> nonNegativeNumber(const std::string& key) const;
  /// A number in [lo, hi].
  std::optional<double> numberInRange(const std::string& key, double lo, double hi) const;
  std::optional<int> integer(const std::string& key) const;
  std::optional<bool> boolean(const std::string& key) const;
  /// One of `choices`.
  std::optional<std::string> choice(const std::string& key,
                                    const std::vector<std::string>& choices) const;
  std::optional<std::string> text(const std::string& key) const;
  std::optional<pbd::Vector3> vector3(const std::string& key) const;
  /// A non-zero vector, normalised.
  std::optional<pbd::Vector3> direction(const std::string& key) const;

  /// Throws std::invalid_argument "analytic reference 'model': parameter 'key': expected ...".
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;
  /// Throws std::invalid_argument "analytic reference 'model': message".
  [[noreturn]] void failModel(const std::string& message) const;

 private:
  std::string model_;
  nlohmann::json json_;
};

}  // namespace pbdval
