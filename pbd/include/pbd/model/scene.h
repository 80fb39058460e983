// Scene: the engine-neutral, plain-data description of a simulation.
//
// The loader (pbd/io/scene_loader.h) fills it from the seed's scene JSON; every engine (the
// PBD library, Bullet, ODE, MuJoCo) is built from the same Scene, and the validation metrics
// read masses, inertias, anchors and axes from it. Mass properties are computed once, by the
// loader, so every engine receives the same numbers.
//
// Frames and units: SI units; all positions, axes and velocities are in the world frame of
// the scene file, at t = 0. A rigid body's *scene frame* is the frame its geometry file is
// given in (after `scale`); its pose is (translation, rotation). Its *principal frame* sits at
// the centre of mass, aligned with the principal axes of inertia.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pbd/collision/grid_interpolation.h"
#include "pbd/math/types.h"
#include "pbd/model/mass_properties.h"
#include "pbd/model/mesh.h"

namespace pbd {

/// A pose's rotation as the scene file gave it (`rotationAxis`, `rotationAngle`): the writer
/// (pbd/io/scene_writer.h) writes it back as given, so that a written scene loads to the same
/// quaternion bit for bit. Absent when the file gave no rotation (or not both keys).
struct GivenRotation {
  Vector3 axis = Vector3::UnitZ();
  Real angle = 0;
};

/// `collisionObjectType` of the seed.
enum class CollisionObjectType : int {
  None = 0,
  Sphere = 1,
  Box = 2,
  Cylinder = 3,
  Torus = 4,
  SignedDistanceField = 5,
  HollowSphere = 6,
  HollowBox = 7,
};

/// How the friction and restitution of two bodies combine into the pair's values
/// (`Simulation.contactCombineRule`). The seed's rule is restitution = e_a·e_b and friction =
/// μ_a + μ_b; Bullet multiplies both, MuJoCo takes the maximum, ODE leaves it to the caller.
enum class ContactCombineRule : int { Seed, Product, Average, Min, Max };

const char* contactCombineRuleName(ContactCombineRule rule);

struct ContactMaterial {
  Real friction = 0;
  Real restitution = 0;
};

/// Combines two materials by `rule`.
ContactMaterial combineMaterials(ContactCombineRule rule, const ContactMaterial& a,
                                 const ContactMaterial& b);

/// Which contact model the PBD library solves (`Simulation.contactModel`, an extension; see
/// docs/contacts.md). `Seed` reproduces PositionBasedDynamics 2.2.2, flaws included:
/// restitution on resting contacts, friction capped per iteration with a tangent frozen at
/// detection. `Corrected` applies restitution only above an approach speed of 2|g|h and
/// bounds the accumulated friction impulse by the Coulomb cone, re-evaluating the sliding
/// direction every iteration.
enum class ContactModel : int { Seed, Corrected };

const char* contactModelName(ContactModel model);

/// Which geometry generates the contacts between rigid bodies (`Simulation.contactGeometry`, an
/// extension; docs/contacts.md#primitive-contacts). `Samples` is the seed's: the surface
/// samples of one body against the signed distance function of the other, both ways.
/// `Primitives` gives the pairs with a closed form (sphere–sphere, sphere against a box,
/// cylinder or hollow shape, box–box, a sphere or box inside a hollow box) their exact contacts
/// (collision/primitive_contacts.h), and keeps the samples for every other pair.
enum class ContactGeometry : int { Samples, Primitives };

const char* contactGeometryName(ContactGeometry geometry);

/// Explicit values for one pair of bodies (`ContactPairs` block); a missing value falls back to
/// the combination rule.
struct ContactPairDesc {
  std::string jsonPath;
  int bodyId1 = -1, bodyId2 = -1;
  int body1 = -1, body2 = -1;  ///< indices into Scene::rigidBodies
  bool hasFriction = false, hasRestitution = false;
  Real friction = 0, restitution = 0;
};

/// The collision keys shared by rigid bodies and tet models.
class DistanceGrid;

struct CollisionObjectDesc {
  CollisionObjectType type = CollisionObjectType::None;
  std::string fileName;  ///< resolved path of `collisionObjectFileName`; empty: use the geometry
  /// The OBJ mesh of `fileName` as in the file (unscaled; collisionObjectScale applies). Null
  /// without `fileName`.
  std::shared_ptr<const TriangleMesh> mesh;
  /// A Discregrid `.csdf` given as `collisionObjectFileName` (type 5): its resolved path and its
  /// distance field, read by the loader (io/discregrid_file.h). The cubic Lagrange grid (the
  /// `pbd` method) is this one; the Catmull-Rom grid is rebuilt from the geometry at the file's
  /// resolution. Empty / null without such a file.
  std::string discregridFile;
  std::shared_ptr<const DistanceGrid> discregridGrid;
  bool testMesh = true;
  /// Meaning by type: sphere radius = [0]; box full extents; cylinder (radius, height);
  /// torus (R, r); hollow sphere radius [0]; hollow box extents; SDF scale.
  Vector3 scale = Vector3::Ones();
  bool invertSDF = false;
  Real thicknessSDF = Real(0.1);
  Vector3i resolutionSDF = Vector3i(10, 10, 10);
};

struct RigidBodyDesc {
  int id = 0;
  std::string jsonPath;  ///< "RigidBodies[3]", for messages
  bool isDynamic = true;
  Real density = 1;
  std::string geometryFile;                  ///< resolved path; empty for a primitive without mesh
  std::shared_ptr<const TriangleMesh> mesh;  ///< scaled, in the scene frame; null without file
  Vector3 translation = Vector3::Zero();
  Quaternion rotation = Quaternion::Identity();  ///< from rotationAxis / rotationAngle
  std::optional<GivenRotation> givenRotation;    ///< as the file gave it (for the writer)
  Vector3 scale = Vector3::Ones();
  Vector3 velocity = Vector3::Zero();         ///< of the centre of mass, world
  Vector3 angularVelocity = Vector3::Zero();  ///< world
  Real restitution = Real(0.6);
  Real friction = Real(0.2);
  bool flatShading = false;
  CollisionObjectDesc collision;
  /// Computed by the loader (volume integration or closed form), or overridden by the scene's
  /// `mass` / `inertia` keys. Used for every engine.
  MassProperties massProperties;
  /// The `mass` and `inertia` keys as given (extensions), for the writer; massProperties
  /// already holds their effect.
  std::optional<Real> givenMass;
  std::optional<Vector3> givenInertia;

  /// World position of the centre of mass at t = 0.
  Vector3 initialCenterOfMass() const {
    return translation + rotation * massProperties.centerOfMass;
  }
  /// World orientation of the principal frame at t = 0.
  Quaternion initialPrincipalRotation() const {
    return (rotation * massProperties.principalRotation).normalized();
  }
};

/// Every joint block of the seed, in the order the loader creates them.
enum class JointType : int {
  Ball,
  BallOnLine,
  Hinge,
  Universal,
  Slider,
  RigidBodyParticleBall,
  RigidBodySpring,
  Distance,
  Damper,
  TargetAngleMotorHinge,
  TargetVelocityMotorHinge,
  TargetPositionMotorSlider,
  TargetVelocityMotorSlider,
  StiffRod,  ///< `CosseratJoints` of the seed's stiff-rods loader
             ///< (joints/stretch_bending_twisting_joint.h)
};
inline constexpr int kJointTypeCount = 14;

/// The scene block name of a joint type ("HingeJoints").
const char* jointBlockName(JointType type);
/// A short stable name ("hinge", "target_angle_motor_hinge") used in results and docs.
const char* jointTypeName(JointType type);

/// A motor's set point: a constant `target`, or a `targetSequence` of (time, value) pairs
/// interpolated linearly, holding the first value before the first sample and the last value
/// after the last one, optionally repeated with period t_last − t_first.
struct MotorTarget {
  Real constant = 0;
  std::vector<Real> times;   ///< strictly increasing; empty: use `constant`
  std::vector<Real> values;  ///< same size as `times`
  bool repeat = false;
  bool repeatGiven = false;  ///< the scene gave `repeatSequence`

  bool hasSequence() const { return !times.empty(); }
  Real valueAt(Real time) const;
  /// The seed's evaluation (TimeStepController::step): `constant` before t = 0 (the value its
  /// loader sets for the first step: `target`, or 0 with a sequence); with a sequence, while
  /// t > T (T = last time − first time) t −= T when repeating — and the seed repeats when the
  /// scene does not give `repeatSequence` (its loader leaves the flag uninitialised, true in
  /// the recorded build) — then linear interpolation between the bracketing samples, the last
  /// value past the end.
  Real seedValueAt(Real time) const;
};

/// A stiff-rod joint's material and geometry (JointType::StiffRod; Deul, Müller, Bender 2018).
/// The loader fills it from the joint's TreeModel and the two segments' shapes
/// (docs/scene-format.md#cosseratjoints-and-treemodels).
struct StiffRodJointParams {
  int id = -1;                    ///< the CosseratJoint's `id`
  int tree = -1;                  ///< index into Scene::stiffRodTrees
  Real youngsModulus = 0;         ///< E, Pa
  Real torsionModulus = 0;        ///< G, Pa
  Real averageRadius = 0;         ///< r of the circular cross-section, m (I = π r⁴ / 4)
  Real averageSegmentLength = 0;  ///< L, m: mean length of the two segments along their y axes
  Vector3 stiffnessModifier = Vector3::Ones();  ///< factors on (E I, 2 G I, E I)
};

/// Which of two formulations a joint with a documented difference from the seed uses
/// (`Simulation.jointModel`, docs/methods.md "Joints"): the seed's own (`seed`) or pbdval's
/// consistent one (`corrected`). Today the damper joint's linear rows.
enum class JointModel : int { Seed, Corrected };

const char* jointModelName(JointModel model);

struct JointDesc {
  JointType type = JointType::Ball;
  std::string jsonPath;  ///< "HingeJoints[0]"
  int bodyId1 = -1;      ///< scene ids as written (rbID for the particle joint)
  int bodyId2 = -1;
  int body1 = -1;                       ///< indices into Scene::rigidBodies, resolved by the loader
  int body2 = -1;                       ///< -1 for the rigid-body–particle joint
  int particle = -1;                    ///< global particle index (RigidBodyParticleBallJoints)
  Vector3 position = Vector3::Zero();   ///< connector / point on the axis (world, t = 0)
  Vector3 position1 = Vector3::Zero();  ///< connector on body 1 (distance joint, spring)
  Vector3 position2 = Vector3::Zero();  ///< connector on body 2
  Vector3 axis = Vector3::UnitX();      ///< unit; hinge, slider, motors, damper, ball-on-line
  Vector3 axis1 = Vector3::UnitX();     ///< unit; universal joint, fixed in body 1
  Vector3 axis2 = Vector3::UnitY();     ///< unit; universal joint, fixed in body 2
  Real stiffness = 0;                   ///< spring and damper joints, N/m
  MotorTarget target;                   ///< motors only
  StiffRodJointParams stiffRod;         ///< stiff-rod joints only
  /// Not a scene key of the joint: buildWorld sets it from Simulation.jointModel (jointModelFor).
  JointModel model = JointModel::Seed;
};

/// How the joints of a stiff-rod tree are solved (`TreeModels[i].solverType`).
enum class StiffRodSolver : int {
  Iterative =
      0,  ///< pbdval extension: one StretchBendingTwisting constraint per joint (Gauss–Seidel)
  Direct = 12,  ///< the seed's value: the tree-structured direct solver (stiff_rod_tree_solver.h)
};

/// A `TreeModels` entry of the seed's stiff-rods format: segments (rigid bodies) joined by
/// stiff-rod joints, with one material.
struct StiffRodTreeDesc {
  int id = 0;
  std::string jsonPath;
  std::vector<int> bodies;          ///< indices into Scene::rigidBodies (`rbIds`)
  std::vector<int> joints;          ///< indices into Scene::joints (`jIds`)
  std::vector<int> staticSegments;  ///< indices into Scene::rigidBodies, made static
  Real youngsModulus = 0;           ///< Pa
  Real torsionModulus = 0;          ///< Pa
  StiffRodSolver solver = StiffRodSolver::Direct;
};

/// One particle of a triangle or tet model (the seed gives every particle mass 1, static ones 0).
struct ParticleDesc {
  Vector3 position = Vector3::Zero();
  Vector3 velocity = Vector3::Zero();
  Real mass = 1;
};

struct TriangleModelDesc {
  int id = 0;
  std::string jsonPath;
  std::string geometryFile;
  TriangleMesh mesh;  ///< transformed to world: R · (v ∘ scale) + translation
  Vector3 translation = Vector3::Zero();
  Quaternion rotation = Quaternion::Identity();
  std::optional<GivenRotation> givenRotation;
  Vector3 scale = Vector3::Ones();
  std::vector<int> staticParticles;
  Real restitution = Real(0.1);
  Real friction = Real(0.2);
  /// kg/m²: particle masses lumped from the triangles' areas (model/mass_properties.h). Unset:
  /// every vertex has mass 1, as in the seed (the model's mass grows with refinement).
  std::optional<Real> density;
  int firstParticle = 0;  ///< index of its first vertex in Scene::particles
};

struct TetModelDesc {
  int id = 0;
  std::string jsonPath;
  std::string nodeFile, eleFile, visFile;
  TetMesh mesh;                                 ///< transformed to world
  std::shared_ptr<const TriangleMesh> visMesh;  ///< transformed to world; null without visFile
  Vector3 translation = Vector3::Zero();
  Quaternion rotation = Quaternion::Identity();
  std::optional<GivenRotation> givenRotation;
  Vector3 scale = Vector3::Ones();
  std::vector<int> staticParticles;
  Real restitution = Real(0.1);
  Real friction = Real(0.2);
  CollisionObjectDesc collision;
  /// kg/m³: particle masses lumped from the tets' volumes (model/mass_properties.h). Unset:
  /// every vertex has mass 1, as in the seed.
  std::optional<Real> density;
  int firstParticle = 0;
};

/// Extension (pbdval's; the seed builds rods in code only): a Cosserat rod of the `LineModels`
/// block (constraints/cosserat_rod.h, docs/scene-format.md#linemodels). Particles p₀ … p_N at
/// `points`, one segment (p_k, p_{k+1}) with an orientation per consecutive pair.
struct LineModelDesc {
  int id = 0;
  std::string jsonPath;
  std::vector<Vector3> points;       ///< world, at least 2, consecutive points distinct
  std::vector<int> staticParticles;  ///< indices into `points`
  std::vector<int> staticSegments;   ///< segment indices whose orientation is fixed
  std::optional<Real> radius;        ///< m (cross-section radius)
  /// kg/m³: particle masses lumped from the segments' volumes ρπr²ℓ (half to each end) and each
  /// segment's quaternion given the inertia ½ m_s r² (isotropic). Unset: the seed's mass 1 per
  /// particle and quaternion "mass" 1.
  std::optional<Real> density;
  /// Pa; both given: the XPBD variant with physical moduli, else the PBD variant with the
  /// Simulation block's rod_* fractions.
  std::optional<Real> youngsModulus, shearModulus;
  Real shearFactor = 1;  ///< Timoshenko κ of the shear rows (κGA), XPBD only
  /// Computed by appendLineModel: each segment's rest frame (d₃ along the segment; the first
  /// frame d₁ = normalise(d₃ × e_y), or d₃ × e_x when |d₃ · e_y| > 0.99, d₂ = d₃ × d₁; the
  /// next frames by parallel transport, the minimal rotation between consecutive tangents).
  std::vector<Quaternion> frames;
  int firstParticle = 0;  ///< index of p₀ in Scene::particles
  int firstSegment = 0;   ///< index of its first segment across all line models

  bool usesModuli() const { return youngsModulus.has_value() && shearModulus.has_value(); }
  std::size_t segmentCount() const { return points.size() - 1; }
  /// w_q of segment k (constraints/cosserat_rod.h): 0 when static, 1 without a density (the
  /// seed's), else 1/(4 I) with I = ½ ρπr²ℓ r².
  Real segmentInverseMass(std::size_t segment) const;
};

/// The parallel-transported rest frames of a polyline (LineModelDesc::frames). Throws
/// std::invalid_argument naming the segment for a zero-length segment or a reversal (two
/// consecutive tangents with cosine below −0.999, where transport is undefined).
std::vector<Quaternion> lineModelFrames(const std::vector<Vector3>& points);

/// `points` + 1 points on a helix about the vertical axis through `center`: point i at angle
/// φ = 2π turns i/points, at center + (R cos φ, −pitch φ/(2π), R sin φ) (it starts at
/// center + (R, 0, 0) and descends by `pitch` per turn).
std::vector<Vector3> helixPoints(Real radius, Real pitch, Real turns, int segments,
                                 const Vector3& center);

struct Scene;

/// Appends the model's particles to scene.particles (masses lumped or 1, static ones 0), sets
/// its frames, firstParticle and firstSegment, and adds it to scene.lineModels. Rod particles
/// come after the triangle- and tet-model particles: call it after those are read.
void appendLineModel(Scene& scene, LineModelDesc model);

/// An axis-aligned box [min, max].
struct AxisAlignedBox {
  Vector3 min = Vector3::Zero();
  Vector3 max = Vector3::Zero();
};

/// How a fluid's step is computed (`FluidModels[].formulation`, docs/methods.md#fluids).
/// `Symmetric`: pbdval's (neighbour lists by index, symmetric XSPH on fresh densities, kernels
/// zero beyond their support). `Seed`: the seed's FluidDemo (TimeStepFluidModel,
/// PositionBasedFluids, CubicKernel) operation for operation: one list per particle, fluid and
/// boundary mixed in its spatial hash's cell order, capped at 60; its kernel expressions without
/// the support test; XSPH updated in place with m/ρ_j and the last iteration's densities.
enum class FluidFormulation : int { Symmetric, Seed };

const char* fluidFormulationName(FluidFormulation formulation);

/// Extension (pbdval's; the seed's fluids are demo-only, without a scene key): a
/// position-based fluid (`FluidModels[]`, docs/scene-format.md#fluidmodels; the solver in
/// constraints/fluid_density.h and fluids/fluid_model.h). Its particles are ordinary particles
/// of Scene::particles, appended after every other particle model; the container's boundary
/// particles are not (the World keeps them with the fluid).
struct FluidModelDesc {
  std::string jsonPath;
  Real particleRadius = Real(0.025);        ///< r: lattice spacing 2r, kernel support 4r
  Real density0 = 1000;                     ///< rest density ρ₀, kg/m³
  Real viscosity = Real(0.02);              ///< XSPH coefficient (dimensionless)
  int iterations = 5;                       ///< Jacobi density iterations per substep
  std::vector<AxisAlignedBox> blocks;       ///< filled on a lattice of spacing 2r
  std::optional<AxisAlignedBox> container;  ///< walls sampled with boundary particles
  /// Listed particles (after the blocks'), at exactly the given positions.
  std::vector<Vector3> particles;
  /// Boxes sampled with boundary particles as the seed's FluidDemo samples its walls (addWall):
  /// min + 2r (j, k, l) for j ≤ floor(extent_x / 2r) …, overlaps kept.
  std::vector<AxisAlignedBox> boundaryWalls;
  /// Extension; unset: the method's own (fluidFormulationFor).
  std::optional<FluidFormulation> formulation;
  int firstParticle = 0;  ///< index of its first particle in Scene::particles
  int particleCount = 0;

  /// The seed's particle mass 0.8 (2r)³ ρ₀.
  Real particleMass() const {
    const Real d = 2 * particleRadius;
    return Real(0.8) * d * d * d * density0;
  }
};

/// Which step World::step takes. `Seed` is the seed's algorithm (step/step_controller.h);
/// `Xpbd` is Müller et al. 2020's substepping with position-level contacts
/// (step/xpbd_step.h). Selected by the method (`pbd` / `pbd.xpbd`), not by the scene file.
enum class StepMethod : int { Seed, Xpbd };

const char* stepMethodName(StepMethod method);

/// Where the XPBD step takes a joint's constraint directions (its Jacobians: lever arms, axes,
/// the inverse inertias in K and the directions the correction is applied along) for the one
/// projection of a substep. C itself is always evaluated at the current poses.
///   Predicted: at the current (predicted, then partly corrected) poses, as PBD and XPBD do —
///     Goldenthal et al. 2007's "implicit constraint direction", first order with numerical
///     damping;
///   Start: at the poses of the substep's start (RigidBodyStates::oldPosition/oldRotation), as
///     SHAKE does (Ryckaert, Ciccotti, Berendsen 1977): the constraint force of the substep
///     acts along the constraint gradient of its start (docs/methods.md, "pbd.xpbd").
enum class JointDirections : int { Start, Predicted };

const char* jointDirectionsName(JointDirections directions);

/// Parameters of the XPBD step (docs/methods.md, "pbd.xpbd"). Compliances are inverse
/// stiffnesses per constraint family; 0 is rigid. Springs and the damper joint keep their own
/// stiffness from the scene.
struct XpbdSettings {
  int substeps = 20;                ///< substeps per step, one position iteration each
  Real jointLinearCompliance = 0;   ///< m/N: point, axis and distance rows of the joints
  Real jointAngularCompliance = 0;  ///< rad/(N m): rotation rows of the joints
  Real contactCompliance = 0;       ///< m/N: contact normal rows
  /// Contacts are collected once per step for points within contactTolerance +
  /// speculativeMargin · h · (|v| + |ω| ρ + h |a|) of another body (ρ the body's sample
  /// radius, a its acceleration).
  Real speculativeMargin = 2;
  /// Joint damping (1/s, the paper's §3.6; joints/xpbd_joint_damping.h): the relative velocity
  /// of a joint's anchors and the relative angular velocity fall by min(μ h, 1) per substep.
  Real jointLinearDamping = 0;
  Real jointAngularDamping = 0;
  /// The joints' constraint directions (every joint but the stiff-rod ones; contacts are not
  /// joints).
  JointDirections jointDirections = JointDirections::Predicted;
  /// Gauss–Seidel sweeps over the joints in every substep (≥ 1; the stiff-rod trees, the
  /// particle constraints and the contacts keep one): the first with λ from zero, the others
  /// continuing λ, all along jointDirections (joints/xpbd_joint.h; docs/methods.md, "Joint
  /// directions").
  int jointIterations = 1;
};

/// The `Simulation` block: every key the seed documents, with the seed's code defaults.
struct SimulationSettings {
  Real timeStepSize = Real(0.005);
  Vector3 gravitation = Vector3(0, Real(-9.81), 0);
  int subSteps = 5;
  int maxIterations = 1;
  int maxIterationsV = 5;
  int velocityUpdateMethod = 0;  ///< 0 first order (the seed's code default), 1 second order
  Real contactTolerance = Real(0.01);
  Real contactStiffnessRigidBody = 1;
  Real contactStiffnessParticleRigidBody = 100;
  ContactCombineRule contactCombineRule = ContactCombineRule::Seed;  ///< extension
  ContactModel contactModel = ContactModel::Seed;                    ///< extension
  /// Extension; unset: the method's own (distanceGridFor).
  std::optional<GridInterpolation> distanceGrid;
  /// Extension; unset: the method's own (femCutoffFor). The FEM triangle and FEM tet solves
  /// (PBD and XPBD) and the isometric bending solves (PBD and XPBD; above 0 in the seed's
  /// form, docs/seed.md "XPBD isometric bending scale") skip an element whose weighted
  /// gradient sum Σ w_i |∇_iC|² (for XPBD tets plus α̃ C²) is below it, and the FEM builders
  /// drop an element whose rest matrix has |det D_m| ≤ it (docs/methods.md, "Particle
  /// constraints"). Above 0 it also selects the seed's forms of the dihedral bending, the
  /// volume constraint, the strain-based tets (with this cut-off) and the strain-based
  /// triangles (docs/methods.md, "The seed's forms").
  std::optional<Real> femCutoff;
  /// Extension; unset: the method's own (jointModelFor).
  std::optional<JointModel> jointModel;
  /// Extension; unset: the method's own (contactGeometryFor).
  std::optional<ContactGeometry> contactGeometry;
  /// Extension: how the scene's OBJ meshes are read (model/mesh.h); `single` as the seed.
  /// Read before the meshes, so a scene-file key only (`--set` refuses it).
  ObjPrecision objPrecision = ObjPrecision::Single;
  StepMethod stepMethod = StepMethod::Seed;  ///< extension (set by the method, not the file)
  XpbdSettings xpbd;                         ///< used when stepMethod == StepMethod::Xpbd
  /// Threads of the collision detection's narrow phase (the method parameter `threads`, not a
  /// scene key): results are bitwise the same for every count (collision_detection.h).
  int detectionThreads = 1;

  int clothSimulationMethod = 2;
  int clothBendingMethod = 2;
  /// Unset: the value the seed forces for the method when the scene does not give it
  /// (clothStiffnessFor: 1, or 10⁵ N/m for XPBD distance constraints, method 4).
  std::optional<Real> cloth_stiffness;
  /// Unset: 0.01, or 100 for XPBD isometric bending (clothBendingMethod 3), as the seed forces
  /// (clothBendingStiffnessFor).
  std::optional<Real> cloth_bendingStiffness;
  Real cloth_xxStiffness = 1;
  Real cloth_yyStiffness = 1;
  Real cloth_xyStiffness = 1;
  Real cloth_xyPoissonRatio = Real(0.3);
  Real cloth_yxPoissonRatio = Real(0.3);
  bool cloth_normalizeStretch = false;
  bool cloth_normalizeShear = false;

  int solidSimulationMethod = 2;
  /// Unset: the seed's forced value for the method (solidStiffnessFor: 1, 10⁶ for FEM-XPBD
  /// (method 3), 10⁵ N/m for XPBD distance constraints (method 6)).
  std::optional<Real> solid_stiffness;
  Real solid_poissonRatio = Real(0.3);
  /// Unset: 1, or 10⁵ N/m⁵ for XPBD volume constraints (method 6) (solidVolumeStiffnessFor).
  std::optional<Real> solid_volumeStiffness;
  bool solid_normalizeStretch = false;
  bool solid_normalizeShear = false;

  Real rod_stretchingStiffness = 1;
  Real rod_shearingStiffnessX = 1;
  Real rod_shearingStiffnessY = 1;
  Real rod_bendingStiffnessX = Real(0.5);
  Real rod_bendingStiffnessY = Real(0.5);
  Real rod_twistingStiffness = Real(0.5);
};

/// The deformables' stiffness as used: the scene's value, else what the seed's
/// initTriangleModelConstraints / initTetModelConstraints force for the method
/// (docs/seed.md#defaults): cloth 1, 10⁵ N/m with clothSimulationMethod 4; solid 1, 10⁶ with
/// solidSimulationMethod 3, 10⁵ N/m with 6; solid volume 1, 10⁵ N/m⁵ with 6.
Real clothStiffnessFor(const SimulationSettings& settings);
/// cloth_bendingStiffness, else 0.01, or 100 with clothBendingMethod 3.
Real clothBendingStiffnessFor(const SimulationSettings& settings);
Real solidStiffnessFor(const SimulationSettings& settings);
Real solidVolumeStiffnessFor(const SimulationSettings& settings);

/// `Simulation.jointModel` when the scene gives it, else the method's own: `seed` for `pbd`,
/// `corrected` for `pbd.xpbd`.
JointModel jointModelFor(const SimulationSettings& settings);

/// A fluid's `formulation` when its FluidModels entry gives it, else the method's own: `seed` for
/// the `pbd` method (its fidelity to PositionBasedDynamics' FluidDemo), `symmetric` for
/// `pbd.xpbd` (momentum-conserving XSPH, the kernel zero past its support: docs/methods.md#fluids).
FluidFormulation fluidFormulationFor(const FluidModelDesc& model,
                                     const SimulationSettings& settings);

/// `Simulation.contactGeometry` when the scene gives it, else the method's own: the seed's
/// `samples` for `pbd` (its fidelity to PositionBasedDynamics), `primitives` for `pbd.xpbd`.
ContactGeometry contactGeometryFor(const SimulationSettings& settings);

/// The seed's absolute threshold 10⁻⁶ of its FEM solves (PositionBasedDynamics.cpp, XPBD.cpp).
inline constexpr Real kSeedFemCutoff = Real(1e-6);

/// `Simulation.femCutoff` when the scene gives it, else the method's own: the seed's 10⁻⁶ for
/// the `pbd` method (its fidelity to PositionBasedDynamics), 0 for `pbd.xpbd` (an element is
/// skipped only at rest: an absolute threshold on Σ w|∇C|² depends on the units and the mesh
/// size, and freezes the small strains of stiff solids).
Real femCutoffFor(const SimulationSettings& settings);

/// The grid interpolation of type-5 shapes: `Simulation.distanceGrid` when the scene gives it,
/// else the method's own: the seed's cubic Lagrange grid for the `pbd` method (its fidelity to
/// PositionBasedDynamics), pbdval's Catmull-Rom grid for `pbd.xpbd` (C¹, and padded widely
/// enough for XPBD's speculative contacts; docs/contacts.md#grid-sdfs).
GridInterpolation distanceGridFor(const SimulationSettings& settings);

/// Keys of the seed's viewer (DemoBase). Parsed and kept; a headless run ignores them, except
/// that `pauseAt` > 0 serves as the default duration of `pbdval simulate`, and exportOBJ,
/// exportPLY, exportFPS as the defaults of its mesh export (--export-dir).
struct ViewerSettings {
  bool pause = true;
  Real pauseAt = -1;
  int numberOfStepsPerRenderUpdate = 8;
  bool renderTets = false, renderTets0 = false, renderContacts = false, renderAABB = false,
       renderSDF = false;
  int renderBVHDepth = -1, renderBVHDepthTets = -1;
  bool exportOBJ = false, exportPLY = false;
  Real exportFPS = 25;
  Vector3 cameraPosition = Vector3(5, 10, 30);
  Vector3 cameraLookat = Vector3(5, 0, 0);
};

struct Scene {
  std::string sourceFile;  ///< path of the JSON file it was loaded from
  std::string name;
  SimulationSettings simulation;
  ViewerSettings viewer;
  std::vector<RigidBodyDesc> rigidBodies;
  std::vector<JointDesc> joints;  ///< in creation order (block order of JointType, then file order)
  std::vector<TriangleModelDesc> triangleModels;
  std::vector<TetModelDesc> tetModels;
  std::vector<LineModelDesc> lineModels;  ///< extension: Cosserat rods
  /// Extension: position-based fluids; their particles come last in `particles`.
  std::vector<FluidModelDesc> fluidModels;
  /// All model vertices: triangle models first, then tets, then line models (rods), then the
  /// fluids' particles.
  std::vector<ParticleDesc> particles;
  std::vector<ContactPairDesc> contactPairs;    ///< extension: explicit per-pair materials
  std::vector<StiffRodTreeDesc> stiffRodTrees;  ///< `TreeModels` (stiff rods)
  /// The top-level `Validation` block as JSON text (empty when absent). The library does not
  /// read it; validation/ parses it (docs/scene-format.md).
  std::string validationJson;

  /// Index of the rigid body with scene id `id`, or -1.
  int bodyIndexById(int id) const;
  /// The friction and restitution of a contact between rigid bodies `bodyA` and `bodyB`
  /// (indices): an explicit ContactPairs entry where given, else the combination rule. Every
  /// engine uses these values, so the engines' own rules never enter.
  ContactMaterial pairMaterial(int bodyA, int bodyB) const;
  /// The friction and restitution of a contact between particle `particle` (global index)
  /// and rigid body `body`: the particle's triangle or tet model combined with the body by
  /// the combination rule (ContactPairs name rigid bodies only and do not apply).
  ContactMaterial particleMaterial(int particle, int body) const;
};

}  // namespace pbd
