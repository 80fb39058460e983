// What an engine can represent, as data (docs/engines.md#features). A scene is described by the
// features it uses (`sceneFeatureUses`: each shape kind, joint type, particle model method,
// rods, fluids, ...), each at a JSON path; an engine declares once, in a FeatureTable, how it
// maps every feature: native, approximated (with a note saying how) or unsupported (with the
// reason). One generic function, `unsupportedFeatures`, names the unsupported JSON paths of a
// scene from a table; the parity pages (docs/parity-*.md, the report's parity page) are
// generated from the same tables. The anchor is MuJoCo's collision-function table
// (mjCOLLISIONFUNC), where what is supported is an entry in a table.
//
// Keys are dotted ("joint.hinge", "cloth.method.fem"). A table entry may name a group, a prefix
// of keys ("cloth" covers "cloth.method.fem" and "cloth.bending.dihedral"); the most specific
// entry wins. An entry may be restricted to some of the engine's methods; such entries win over
// the entries for every method (ODE's ball-on-line joint: approximated with ode.step,
// unsupported with ode.quickstep).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pbd/model/scene.h"

namespace pbdval {

enum class Support { Native, Approximated, Unsupported };

/// "native", "approximated", "unsupported".
const char* supportName(Support support);
/// The support named `name`; throws std::invalid_argument naming the valid ones.
Support supportNamed(std::string_view name);

/// One scene feature of the vocabulary every table is written in.
struct FeatureInfo {
  const char* key;          ///< "joint.hinge"
  const char* description;  ///< "hinge joint (HingeJoints)"
  /// False for a feature that sceneFeatureUses cannot see from the scene alone (a condition an
  /// engine checks when it runs, e.g. per-pair materials that are not products of per-body
  /// values): tables still declare it, the parity page shows it, the generic function never
  /// reports it.
  bool fromScene = true;
};

/// Every feature, in the order of the parity pages.
const std::vector<FeatureInfo>& sceneFeatures();
/// The feature with `key`, or nullptr.
const FeatureInfo* findFeature(std::string_view key);
/// Whether `key` is a feature or a group of features (a dotted prefix of one: "cloth").
bool isFeatureKeyOrGroup(std::string_view key);

/// One entry of an engine's table.
struct FeatureSupport {
  FeatureSupport() = default;
  FeatureSupport(std::string key_, Support support_, std::string text_ = {},
                 std::vector<std::string> methods_ = {})
      : key(std::move(key_)),
        support(support_),
        text(std::move(text_)),
        methods(std::move(methods_)) {}

  std::string key;  ///< a feature or a group
  Support support = Support::Native;
  /// Native: how (optional). Approximated: how, and how it differs. Unsupported: why.
  std::string text;
  /// The methods this entry is for; empty: every method of the engine.
  std::vector<std::string> methods;
};

/// An engine's declaration of what it supports: one entry per feature or group, together
/// covering every feature of the vocabulary for every method (checkFeatureTable).
struct FeatureTable {
  std::vector<FeatureSupport> entries;

  /// The entry that decides `key` for `method`: the most specific entry restricted to
  /// `method`, else the most specific entry for every method; nullptr when none covers it.
  const FeatureSupport* resolve(std::string_view key, std::string_view method) const;
};

/// Problems of `table` for an engine with `methods`, each naming the entry ("features[3]: ..."):
/// a key that is neither a feature nor a group, a method that is not the engine's, an
/// unsupported or approximated entry without its text, two entries for the same key and
/// method, a feature no entry covers for some method. Empty when the table is sound.
std::vector<std::string> checkFeatureTable(const FeatureTable& table,
                                           const std::vector<std::string>& methods);

/// One use of a feature by a scene: where, and the scene's values that make it this feature.
struct FeatureUse {
  std::string key;       ///< a key of sceneFeatures()
  std::string jsonPath;  ///< "RigidBodies[2]", "TriangleModels[0]"
  std::string detail;    ///< "collisionObjectType 4", "clothSimulationMethod 2"; may be empty
};

/// The features `scene` uses (those with FeatureInfo::fromScene), in scene order.
std::vector<FeatureUse> sceneFeatureUses(const pbd::Scene& scene);

/// One unsupported use: its feature and the message the run reports,
/// "RigidBodies[2]: torus (collisionObjectType 4): MuJoCo has no torus, ...".
struct UnsupportedUse {
  std::string key;
  std::string jsonPath;
  std::string message;
};

/// The uses `table` declares unsupported for `method`, one per JSON path and deciding entry
/// (a cloth model is reported once by an engine without particles, not once per feature), in
/// the order of `uses`. A use no entry covers is unsupported ("not declared by the engine").
std::vector<UnsupportedUse> unsupportedUses(const FeatureTable& table,
                                            const std::vector<FeatureUse>& uses,
                                            std::string_view method);
/// The messages of unsupportedUses(table, sceneFeatureUses(scene), method): what
/// Engine::unsupported returns.
std::vector<std::string> unsupportedFeatures(const FeatureTable& table, const pbd::Scene& scene,
                                             std::string_view method);

}  // namespace pbdval
