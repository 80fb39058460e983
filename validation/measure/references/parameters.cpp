#include "validation/measure/references/parameters.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pbdval {

namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items)
    out += (out.empty() ? "" : ", ") + item;
  return out.empty() ? "none" : out;
}

}  // namespace

ReferenceParameters::ReferenceParameters(std::string model, const std::string& jsonText,
                                         const std::vector<std::string>& known)
    : model_(std::move(model)) {
  try {
    json_ = nlohmann::json::parse(jsonText.empty() ? std::string("{}") : jsonText);
  } catch (const nlohmann::json::exception& e) {
    failModel(std::string("parameters: not valid JSON (") + e.what() + ")");
  }
  if (!json_.is_object()) failModel("parameters: expected an object");
  for (const auto& item : json_.items()) {
    bool isKnown = false;
    for (const std::string& k : known)
      isKnown = isKnown || k == item.key();
    if (!isKnown)
      failModel("unknown parameter '" + item.key() + "' (known: " + joined(known) + ")");
  }
}

void ReferenceParameters::fail(const std::string& key, const std::string& expected) const {
  failModel("parameter '" + key + "': expected " + expected);
}

void ReferenceParameters::failModel(const std::string& message) const {
  throw std::invalid_argument("analytic reference '" + model_ + "': " + message);
}

std::optional<double> ReferenceParameters::number(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_number() || !std::isfinite(value.get<double>())) fail(key, "a number");
  return value.get<double>();
}

std::optional<double> ReferenceParameters::positiveNumber(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_number() || !(value.get<double>() > 0) || !std::isfinite(value.get<double>()))
    fail(key, "a positive number");
  return value.get<double>();
}

std::optional<double> ReferenceParameters::nonNegativeNumber(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_number() || !(value.get<double>() >= 0) || !std::isfinite(value.get<double>()))
    fail(key, "a number ≥ 0");
  return value.get<double>();
}

std::optional<double> ReferenceParameters::numberInRange(const std::string& key, double lo,
                                                         double hi) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_number() || !(value.get<double>() >= lo) || !(value.get<double>() <= hi)) {
    std::ostringstream expected;
    expected << "a number in [" << lo << ", " << hi << "]";
    fail(key, expected.str());
  }
  return value.get<double>();
}

std::optional<int> ReferenceParameters::integer(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_number_integer()) fail(key, "an integer");
  return value.get<int>();
}

std::optional<bool> ReferenceParameters::boolean(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_boolean()) fail(key, "true or false");
  return value.get<bool>();
}

std::optional<std::string> ReferenceParameters::text(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_string()) fail(key, "a string");
  return value.get<std::string>();
}

std::optional<std::string> ReferenceParameters::choice(
    const std::string& key, const std::vector<std::string>& choices) const {
  const std::optional<std::string> value = text(key);
  if (!value) return std::nullopt;
  for (const std::string& c : choices)
    if (c == *value) return value;
  std::string quoted;
  for (const std::string& c : choices)
    quoted += (quoted.empty() ? "\"" : " or \"") + c + "\"";
  fail(key, quoted);
}

std::optional<pbd::Vector3> ReferenceParameters::vector3(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  const nlohmann::json& value = json_.at(key);
  if (!value.is_array() || value.size() != 3) fail(key, "an array of 3 numbers");
  pbd::Vector3 v;
  for (int i = 0; i < 3; ++i) {
    if (!value[std::size_t(i)].is_number()) fail(key, "an array of 3 numbers");
    v[i] = value[std::size_t(i)].get<double>();
  }
  if (!v.allFinite()) fail(key, "an array of 3 finite numbers");
  return v;
}

std::optional<pbd::Vector3> ReferenceParameters::direction(const std::string& key) const {
  const std::optional<pbd::Vector3> v = vector3(key);
  if (!v) return std::nullopt;
  if (!(v->norm() > 0)) fail(key, "a non-zero direction [x, y, z]");
  return v->normalized();
}

}  // namespace pbdval
