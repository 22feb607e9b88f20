// multibody/mechanism.h — the immutable planar mechanism model and its builder: bodies
// (rigid, and flexible with floating frame of reference from a fem::ReducedRod), markers,
// joints (revolute, prismatic, weld, ground), drivers (constant speed, speed profile, DC
// motor), force elements and gravity; plus the layout of the DAE unknowns
// y = [p; v; λ; μ; z]. The builder validates every input and the topology; Build() freezes.
// What does not live here: the residual/Jacobian (multibody/dae.h), the per-run workspace
// (multibody/run_data.h), the integrator (multibody/ida_integrator.h, simulate.h).
//
// Coordinates (ffrf-planar.md): each body b owns p_b = [x, y, θ, q_0 … q_{n−1}] — frame
// origin R = (x, y) in the world [m], frame angle θ [rad], elastic coordinates q (n = 0 for
// a rigid body). v_b = ṗ_b. Rigid bodies are the n = 0 case of the flexible-body equations
// (m, S0 = m c, J0 = I_c + m|c|²), one code path.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "common/eigen.h"
#include "common/matvec.h"
#include "fem/reduced_rod.h"
#include "multibody/force_element.h"

namespace flexrod::multibody {

// J = [[0, −1], [1, 0]], the rotation by +90° of ffrf-planar.md (dA/dt = A J θ̇).
inline Vec2 Jm(const Vec2& a) { return Vec2(-a.y(), a.x()); }   ///< J a
inline Vec2 JTm(const Vec2& a) { return Vec2(a.y(), -a.x()); }  ///< Jᵀ a

// ---- typed indices --------------------------------------------------------------------------
struct BodyId {
  int index{-1};  ///< −1 is the ground
  bool is_ground() const { return index < 0; }
  friend bool operator==(BodyId a, BodyId b) { return a.index == b.index; }
};
inline constexpr BodyId kGround{-1};
struct MarkerId {
  int index{-1};
  friend bool operator==(MarkerId a, MarkerId b) { return a.index == b.index; }
};
struct JointId {
  int index{-1};
};
struct DriverId {
  int index{-1};
};
struct ElementId {
  int index{-1};
};

/// Slots of a body's coordinates: p_b[kX], p_b[kY], p_b[kTheta], p_b[kFirstMode + k] = q_k.
enum BodySlot : int { kX = 0, kY = 1, kTheta = 2, kFirstMode = 3 };

// ---- damping of the elastic coordinates ----------------------------------------------------
/// Frequency-band damping defaults (commercial FE convention, DESIGN.md): ζ = 1 % below
/// 100 Hz, 10 % below 1 kHz, critical (100 %) above.
inline constexpr double kBandLowLimitHz = 100.0;
inline constexpr double kBandHighLimitHz = 1000.0;
inline constexpr double kBandLowRatio = 0.01;
inline constexpr double kBandMidRatio = 0.10;
inline constexpr double kBandHighRatio = 1.0;

enum class DampingKind { kNone, kModalRatio, kFrequencyBand, kRayleigh, kMatrix };

/// Elastic damping D (n×n) in Q_e = −K q − D q̇. Modal kinds solve K φ = ω² M_ff φ once at
/// build time and set D = M_ff Φ diag(2 ζ_i ω_i) Φᵀ M_ff (Φ M_ff-normalised): ratios of the
/// body's own modes, i.e. of the rod clamped to its floating frame. Rayleigh sets
/// D = α M_ff + β K. kMatrix takes D as given, e.g. from ModalDampingForBody
/// (multibody/mechanism_modes.h), which refers the ratios to the modes of the assembled
/// mechanism.
struct DampingSpec {
  DampingKind kind{DampingKind::kNone};
  std::vector<double> modal_ratios;             ///< ζ_i per mode [-], >= 0; one value = all modes
  double band_low_limit_hz{kBandLowLimitHz};    ///< [Hz]
  double band_high_limit_hz{kBandHighLimitHz};  ///< [Hz], > band_low_limit_hz
  double band_low_ratio{kBandLowRatio};         ///< ζ below band_low_limit_hz [-]
  double band_mid_ratio{kBandMidRatio};         ///< ζ between the limits [-]
  double band_high_ratio{kBandHighRatio};       ///< ζ above band_high_limit_hz [-]
  double rayleigh_alpha{0.0};                   ///< α [1/s], >= 0
  double rayleigh_beta{0.0};                    ///< β [s], >= 0
  /// kMatrix: D itself, n×n, symmetric positive semi-definite [generalised N s/m: entry (i, j)
  /// is the force conjugate to q_i per unit q̇_j].
  Mat matrix;

  static DampingSpec None() { return {}; }
  static DampingSpec ModalRatio(std::vector<double> ratios);
  static DampingSpec FrequencyBand();
  /// The band ratio ζ [-] for a mode of frequency f_hz [Hz] (the band_* fields). The ratio does
  /// not jump at a limit: over one octave centred on it (limit / √2 to limit · √2) log ζ runs
  /// linearly in log f from the ratio below to the ratio above, so that a small change of a rod
  /// cannot move a mode from 10 % to critical damping (at the limit itself: the geometric mean
  /// of the two). Outside the transitions the band's constant ratios hold.
  double BandRatio(double f_hz) const {
    const double w = std::sqrt(2.0);  // half an octave each side
    auto across = [&](double limit, double below, double above) {
      const double s = std::log(f_hz / (limit / w)) / std::log(w * w);  // 0 .. 1 over the octave
      return std::exp(std::log(below) + s * (std::log(above) - std::log(below)));
    };
    if (f_hz <= band_low_limit_hz / w) return band_low_ratio;
    if (f_hz < band_low_limit_hz * w)
      return across(band_low_limit_hz, band_low_ratio, band_mid_ratio);
    if (f_hz <= band_high_limit_hz / w) return band_mid_ratio;
    if (f_hz < band_high_limit_hz * w)
      return across(band_high_limit_hz, band_mid_ratio, band_high_ratio);
    return band_high_ratio;
  }
  static DampingSpec Rayleigh(double alpha, double beta);
  static DampingSpec Matrix(Mat d);
  /// Throws InputError naming key.<field>.
  void Validate(const std::string& key, int num_modes) const;
};

// ---- specs (user input, validated by the builder) -----------------------------------------
struct RigidBodySpec {
  std::string name;
  double mass{0.0};     ///< [kg], > 0
  double inertia{0.0};  ///< rotational inertia about the centre of mass [kg m^2], >= 0
  Vec2 com{0.0, 0.0};   ///< centre of mass in the body frame [m]
};

struct FlexibleBodySpec {
  std::string name;
  std::shared_ptr<const fem::ReducedRod> rod;  ///< reduced rod (shared, immutable), non-null
  DampingSpec damping;
  /// Second-order (von Kármán) axial strain. Element e (dofs w_e = Φ_e q) stretches by
  /// δ_e = u_b − u_a and its bending shortens its chord by s_e = ½ w_eᵀ K_G w_e = ½ ∫_e v'² dx;
  /// its axial force is N_e = EA/L_e (P (δ + s))_e and the strain energy Σ_e L_e N_e²/(2 EA).
  /// P projects the shortening field s on the elongation fields the basis can carry (the span
  /// of δ(q), energy-orthogonal; P = I for the full FE rod; P δ = δ up to the singular values
  /// ReducedRod::Elongation drops, below 1e-9 of the largest). The part it removes would be
  /// relieved, at no energy, by axial freedom the reduced basis lacks; keeping it would lock
  /// the reduced rod (an 8-mode Craig–Bampton rod bent 3 mm is then 12 % too stiff). The sum of
  /// s, the approach of the rod's ends, is kept: uniform stretching is always in the span.
  /// Beyond K q the elastic force gains F_g = Σ_e Φ_eᵀ (N_e K_G w_e + EA/L_e (P s)_e d),
  /// d = (−1, 0, 0, 1, 0, 0): the geometric stiffness of the distributed axial force (P-delta)
  /// and the shortening of the bent rod, which the small end's axial coordinate carries. With
  /// the exact frame motion the body is right to second order in the rotations in any attached
  /// frame. The damping acts on the rates of these strains, not on the shortening motion (with
  /// Rayleigh β it is Kelvin–Voigt on them). The force's work is book-kept in the energy balance
  /// (Quadrature::kStiffeningWork).
  bool geometric_stiffening{true};
  /// How the residual evaluates the second-order strain: the same force either way (tests pin
  /// each to compare them); kAuto takes the cheaper (Body::modal_strain_kernel).
  enum class StrainKernel { kAuto, kModal, kElements };
  StrainKernel strain_kernel{StrainKernel::kAuto};
};

struct PrismaticSpec {
  std::string name;
  MarkerId marker_i;           ///< the guide (axis fixed in this marker's frame)
  MarkerId marker_j;           ///< the slider
  Vec2 axis{1.0, 0.0};         ///< sliding direction in marker i's frame (normalised)
  double relative_angle{0.0};  ///< held value of φ_j − φ_i [rad]
  double damping{0.0};         ///< viscous damping along the axis [N s/m], >= 0
  double friction_force{0.0};  ///< Coulomb friction force F_c [N], >= 0
  double friction_regularisation_speed{1e-3};  ///< s_reg in F_c tanh(s/s_reg) [m/s], > 0
};

struct DcMotorSpec {
  double stall_torque{0.0};      ///< motor torque at zero speed [N m], > 0
  double no_load_speed{0.0};     ///< motor speed at zero torque [rad/s], > 0
  double ratio{1.0};             ///< belt ratio: motor speed / body speed [-], > 0
  double flywheel_inertia{0.0};  ///< inertia on the driven body's axis [kg m^2], >= 0
  double rotor_inertia{0.0};     ///< motor rotor inertia, reflected as ratio² J [kg m^2], >= 0
  void Validate(const std::string& key) const;
};

/// Piecewise-linear speed table ω(t) (constant beyond the ends), integrated exactly.
struct SpeedProfile {
  std::vector<double> times;       ///< [s], strictly increasing, >= 2 entries
  std::vector<double> speeds;      ///< [rad/s], same length
  std::vector<double> cumulative;  ///< ∫_{t_0}^{t_k} ω ds at each knot [rad] (set by the builder)
  double Speed(double t) const;    ///< ω(t) [rad/s]
  double Acceleration(double t) const;  ///< dω/dt (right limit at knots) [rad/s^2]
  double Integral(double t) const;      ///< ∫_0^t ω ds [rad]
};

// ---- frozen model data ---------------------------------------------------------------------
struct Body {
  std::string name;
  bool flexible{false};
  int coordinate_offset{0};  ///< index of x in p
  int num_modes{0};          ///< n
  // FFRF inertia shape integrals (ffrf-planar.md); rigid: n = 0.
  double mass{0.0};   ///< m [kg]
  Vec2 S0{0.0, 0.0};  ///< ∫ρ ū₀ [kg m]
  Mat2X Sbar;         ///< ∫ρ S, 2×n [kg]
  double J0{0.0};     ///< ∫ρ ū₀ᵀū₀ about the frame origin, + driver inertia [kg m^2]
  Vec I1;             ///< ∫ρ Sᵀū₀ [kg m]
  Vec Ibar;           ///< ∫ρ SᵀJū₀ [kg m]
  Mat Mff;            ///< ∫ρ SᵀS [kg]
  Mat Stilde;         ///< ∫ρ SᵀJS (skew) [kg]
  double driver_inertia{0.0};  ///< flywheel + reflected rotor inertia included in J0 [kg m^2]
  // Elastic forces.
  Mat K;  ///< n×n
  bool geometric_stiffening{false};
  // The second-order axial strain (geometric stiffening only). Element e joins nodes e and
  // e + 1; its transverse dofs w_e = (v_e, θ_e, v_e+1, θ_e+1) = T_e q, T_e rows 2e … 2e + 3 of T,
  // and G_e = T_eᵀ K_G T_e. The strains live in the r elongation fields V the basis carries
  // (P = V Vᵀ): their modal coordinates are a = W q + σ, σ_k = ½ qᵀ H_k q, and the elements'
  // axial forces N = k V a (dae_kernels.cc UpdateSecondOrderStrain).
  int num_strain_elements{0};           ///< n_e
  double element_axial_stiffness{0.0};  ///< k = E A / L_e [N/m]
  Mat transverse_rows;         ///< T: the (v, θ) rows of Φ at every node (2 (n_e + 1) × n)
  Eigen::Matrix4d element_Kg;  ///< K_G on w_e per newton of tension [1/m]
  /// V (n_e × r), orthonormal columns spanning the elongation fields δ(q) = E q: P = V Vᵀ.
  Mat element_strain_basis;
  /// Rows k n … k n + n − 1: H_k = Σ_e V_ek G_e [1/m] (n r × n), so that the r products
  /// [H_k x] are one matrix-vector product with long columns.
  ProductMatrix strain_tensors;
  Mat strain_elongation;  ///< W = Vᵀ E (r × n): the strain coordinates' linear part [m]
  /// B = E⁺ V (n × r): q̃ = q + B σ(q) has the strains as elongations, E q̃ = V a.
  Mat strain_to_q;
  /// The residual's kernel: H_k q as n × n products (r n² operations), or from the elements
  /// (T q, n_e K_G w_e, Tᵀ: ~8 (n_e + 1) n), whichever is cheaper (the same force; the full-FE
  /// rod, r = n_e, takes the elements). FlexibleBodySpec::strain_kernel.
  bool modal_strain_kernel{true};
  /// D acts on q̃̇, not on q̇ (geometric stiffening with damping): the shortening of the bent
  /// rod, which strains nothing, is not damped.
  bool strain_damping{false};
  Mat D;  ///< n×n damping
  DampingSpec damping;
  Vec modal_frequencies_hz;  ///< eigenfrequencies of (K, M_ff) [Hz] (empty if rigid)
  /// ζ_i used (modal kinds) [-]; empty for kMatrix (its ratios belong to whoever made D).
  Vec modal_damping_ratios;
  std::shared_ptr<const fem::ReducedRod> rod;  ///< null for rigid bodies
  /// UpdateBody's products with q as one matrix-vector product: the rows of S̄ (2), M_ff, S̃, K
  /// (n each) and, with geometric stiffening, W (r), stacked ((2 + 3n + r) × n); and with q̇:
  /// S̃ and, unless strain_damping, D (StackModalProducts). Kept by their non-zeros when those
  /// are few (the full FE rod: banded; ProductMatrix).
  ProductMatrix q_products, qd_products;
  ProductMatrix mass_ff;  ///< M_ff again, for MassTimes (by its non-zeros when banded)
  /// Structural non-zero mask of the q–q block (union of M_ff, S̃, K, D; dense with
  /// geometric stiffening), for the sparse Jacobian pattern.
  std::vector<std::vector<bool>> qq_mask;

  int num_coordinates() const { return 3 + num_modes; }
  int coordinate(int slot) const { return coordinate_offset + slot; }
};

struct Marker {
  std::string name;
  int body{-1};             ///< body index, −1 = ground
  Vec2 position{0.0, 0.0};  ///< ū₀ in the body frame (ground: world) [m]
  double angle{0.0};        ///< orientation of the marker frame relative to the body frame [rad]
  Mat2X S_u;                ///< 2×n elastic displacement rows [m]
  RowVec S_phi;             ///< 1×n elastic rotation row [rad]
  int node{-1};             ///< FE node of a flexible body, −1 otherwise
  /// Body coordinate slots that move this marker (frame slots and q_k with non-zero rows).
  std::vector<int> active_slots;
};

enum class JointKind { kRevolute, kPrismatic, kWeld, kGround };
const char* ToString(JointKind kind);

struct Joint {
  std::string name;
  JointKind kind{JointKind::kRevolute};
  int marker_i{-1};  ///< revolute/prismatic/weld
  int marker_j{-1};
  int body{-1};                    ///< kGround: the grounded body
  Vec2 ground_position{0.0, 0.0};  ///< kGround: held frame origin [m]
  double ground_angle{0.0};        ///< kGround: held frame angle [rad]
  Vec2 axis{1.0, 0.0};             ///< kPrismatic: unit axis in marker i's frame
  double relative_angle{0.0};      ///< kPrismatic/kWeld: held φ_j − φ_i [rad]
  int row{0};                      ///< first constraint row (index into λ and μ)
  int num_rows{0};                 ///< 2 (revolute, prismatic) or 3 (weld, ground)
  int guide_element{-1};           ///< kPrismatic: index of its damper/friction element, or −1
};

enum class DriverKind { kConstantSpeed, kSpeedProfile, kDcMotor };
const char* ToString(DriverKind kind);

struct Driver {
  std::string name;
  DriverKind kind{DriverKind::kConstantSpeed};
  int body{-1};
  double initial_angle{0.0};  ///< θ at t = 0 (constraint drivers) [rad]
  double speed{0.0};          ///< kConstantSpeed: ω [rad/s]
  SpeedProfile profile;       ///< kSpeedProfile
  DcMotorSpec motor;          ///< kDcMotor
  int row{-1};                ///< constraint row (−1 for the motor, which is a force)

  bool is_constraint() const { return kind != DriverKind::kDcMotor; }
  double PrescribedAngle(double t) const;         ///< constraint drivers [rad]
  double PrescribedSpeed(double t) const;         ///< [rad/s]
  double PrescribedAcceleration(double t) const;  ///< [rad/s^2]
  /// DC motor torque on the body at body speed ω: ratio·T_stall·(1 − ratio·ω/ω_noload) [N m].
  double MotorTorque(double body_speed) const;
  double MotorTorqueSlope() const;  ///< dT/dω [N m s]
};

struct ElementSlot {
  std::string name;
  int marker_i{-1};
  int marker_j{-1};
  std::shared_ptr<const ForceElement> element;
  int state_offset{0};  ///< first state in z (relative to the z block)
  int num_states{0};
  int memory_offset{0};  ///< first entry in RunData::element_memory
  int num_memory{0};
  int root_offset{0};  ///< first root among the element roots
  int num_roots{0};
  int joint{-1};  ///< prismatic joint this guide element belongs to, or −1
};

/// Modal damping of a chain of rigid bodies (the exact rod's node bodies, multibody/exact_rod.h)
/// on their deformation rates in a frame turning with the first body; the equations are in
/// multibody/corotated_damping.h. Its r states η (η̇ = w, the modal rates) sit in the z block.
struct CorotatedDamping {
  std::string name;
  std::vector<int> bodies;  ///< body indices, n >= 2; bodies[0] carries the frame
  /// Y, 3(n − 1) × r: modal rates w = Yᵀ ḋ [√kg m/s for M-normalised modes; ḋ in m/s, rad/s]
  Mat modes;
  /// c (r) [1/s for M-normalised modes]: generalized damping forces −Bᵀ Y diag(c) w
  Vec coefficients;
  int state_offset{0};  ///< first of its r states in z (relative to the z block)
  int num_states() const { return static_cast<int>(coefficients.size()); }
};

/// Quadrature states appended to z (energy bookkeeping), in this order.
enum Quadrature : int {
  kDissipatedElements = 0,  ///< ∫ Σ element dissipation dt [J]
  kDissipatedDamping = 1,   ///< ∫ Σ q̇ᵀ D q̇ dt (modal/Rayleigh/co-rotated damping) [J]
  kDriverWork = 2,          ///< ∫ Σ driver torque · θ̇ dt [J]
  kStiffeningWork = 3,  ///< ∫ Σ q̇ᵀ(−F_g(q)) dt (FlexibleBodySpec::geometric_stiffening) [J]
  kNumQuadratures = 4
};

/// The immutable mechanism. Layout of the DAE unknowns:
/// y = [p (np) | v (np) | λ (nc) | μ (nc) | z_elements (nze) | z_quadrature (4)]; z_elements
/// holds the force elements' states and the co-rotated dampings' modal states.
class Mechanism {
 public:
  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  int num_coordinates() const { return num_coordinates_; }  ///< np
  int num_constraints() const { return num_constraints_; }  ///< nc
  int num_element_states() const { return num_element_states_; }
  int num_element_memory() const { return num_element_memory_; }
  int num_element_roots() const { return num_element_roots_; }
  int size() const {
    return 2 * num_coordinates_ + 2 * num_constraints_ + num_element_states_ + kNumQuadratures;
  }  ///< N
  int max_body_coordinates() const { return max_body_coordinates_; }

  int p_offset() const { return 0; }
  int v_offset() const { return num_coordinates_; }
  int lambda_offset() const { return 2 * num_coordinates_; }
  int mu_offset() const { return 2 * num_coordinates_ + num_constraints_; }
  int z_offset() const { return 2 * num_coordinates_ + 2 * num_constraints_; }
  int quadrature_offset() const { return z_offset() + num_element_states_; }

  const std::vector<Body>& bodies() const { return bodies_; }
  const std::vector<Marker>& markers() const { return markers_; }
  const std::vector<Joint>& joints() const { return joints_; }
  const std::vector<Driver>& drivers() const { return drivers_; }
  const std::vector<ElementSlot>& elements() const { return elements_; }
  const std::vector<CorotatedDamping>& corotated_dampings() const { return corotated_; }
  const Body& body(BodyId id) const { return bodies_.at(id.index); }
  const Marker& marker(MarkerId id) const { return markers_.at(id.index); }
  const Joint& joint(JointId id) const { return joints_.at(id.index); }
  const Driver& driver(DriverId id) const { return drivers_.at(id.index); }
  const ElementSlot& element(ElementId id) const { return elements_.at(id.index); }
  const Vec2& gravity() const { return gravity_; }  ///< [m/s^2]

  /// Index in p (and v) of a body slot (kX, kY, kTheta, kFirstMode + k).
  int coordinate(BodyId body, int slot) const;

  /// Lookup by name; throws InputError(kind, name, "unknown ...") if absent.
  BodyId FindBody(const std::string& name) const;
  MarkerId FindMarker(const std::string& name) const;
  JointId FindJoint(const std::string& name) const;
  DriverId FindDriver(const std::string& name) const;
  ElementId FindElement(const std::string& name) const;

  /// Readable name of unknown y[i], e.g. "v[crank.theta]", "lambda[pin.1]", "z[contact.0]".
  std::string VariableName(int i) const;
  /// Times in (t0, t1) at which a driver's prescribed acceleration jumps (speed-profile knots).
  std::vector<double> Breakpoints(double t0, double t1) const;

 private:
  friend class MechanismBuilder;
  std::vector<Body> bodies_;
  std::vector<Marker> markers_;
  std::vector<Joint> joints_;
  std::vector<Driver> drivers_;
  std::vector<ElementSlot> elements_;
  std::vector<CorotatedDamping> corotated_;
  Vec2 gravity_{0.0, 0.0};
  int num_coordinates_{0}, num_constraints_{0}, num_element_states_{0};
  int num_element_memory_{0}, num_element_roots_{0}, max_body_coordinates_{0};
};

/// Collects bodies, markers, joints, drivers and elements; every Add validates its input
/// (InputError naming the item and field); Build() checks the topology and freezes.
class MechanismBuilder {
 public:
  BodyId AddRigidBody(const RigidBodySpec& spec);
  BodyId AddFlexibleBody(const FlexibleBodySpec& spec);

  /// A fixed point in the world.
  MarkerId AddGroundMarker(const std::string& name, const Vec2& position, double angle = 0.0);
  /// A point fixed in a body frame (on a flexible body: carried by the frame only).
  MarkerId AddBodyMarker(BodyId body, const std::string& name, const Vec2& position,
                         double angle = 0.0);
  /// A point carried by FE node `node` of a flexible body, offset in the rod frame
  /// (ReducedRod::Marker(node, offset)).
  MarkerId AddNodeMarker(BodyId body, const std::string& name, int node,
                         const Vec2& offset = Vec2::Zero(), double angle = 0.0);
  /// A point of a flexible body given by its shape rows directly.
  MarkerId AddShapeMarker(BodyId body, const std::string& name, const fem::MarkerShape& shape,
                          double angle = 0.0);

  JointId AddRevolute(const std::string& name, MarkerId i, MarkerId j);
  /// Prismatic joint; adds its guide element (damper/friction) when either is non-zero.
  JointId AddPrismatic(const PrismaticSpec& spec);
  JointId AddWeld(const std::string& name, MarkerId i, MarkerId j, double relative_angle = 0.0);
  /// Fixes the body's frame coordinates (x, y, θ).
  JointId AddGroundJoint(const std::string& name, BodyId body, const Vec2& position, double angle);

  /// θ_body = θ0 + ω t (rheonomic constraint; its multiplier gives the driver torque).
  DriverId AddConstantSpeedDriver(const std::string& name, BodyId body, double initial_angle,
                                  double speed);
  /// θ_body = θ0 + ∫_0^t ω(s) ds with ω piecewise linear through (times, speeds).
  DriverId AddSpeedProfileDriver(const std::string& name, BodyId body, double initial_angle,
                                 const std::vector<double>& times,
                                 const std::vector<double>& speeds);
  /// DC-motor torque line through a belt ratio; adds the flywheel and reflected rotor
  /// inertia to the body (no constraint).
  DriverId AddDcMotorDriver(const std::string& name, BodyId body, const DcMotorSpec& motor);

  ElementId AddSpringDamper(const std::string& name, MarkerId i, MarkerId j, double stiffness,
                            double damping, double free_length);
  ElementId AddRotationalSpringDamper(const std::string& name, MarkerId i, MarkerId j,
                                      double stiffness, double damping, double free_angle);
  /// A user force element (e.g. the clearance joint).
  ElementId AddForceElement(const std::string& name, MarkerId i, MarkerId j,
                            std::shared_ptr<const ForceElement> element);

  /// Modal damping of the rigid bodies `bodies` (>= 2, in chain order, the first carrying the
  /// frame) on their co-rotated deformation rates (multibody/corotated_damping.h): modes Y
  /// (3(n − 1) × r), coefficients c (r, finite). Throws InputError naming `name`.
  void AddCorotatedDamping(const std::string& name, const std::vector<BodyId>& bodies,
                           const Mat& modes, const Vec& coefficients);

  /// Gravity acceleration vector [m/s^2]; default off (zero).
  void SetGravity(const Vec2& gravity);

  /// Validates the topology and returns the frozen model. The builder cannot be used after.
  Mechanism Build();

 private:
  void CheckNotBuilt() const;
  void CheckName(const std::string& kind, const std::string& name) const;
  void CheckBody(BodyId body, const std::string& key) const;
  void CheckMarker(MarkerId marker, const std::string& key) const;
  int AddMarkerImpl(Marker marker);
  ElementId AddElementImpl(const std::string& name, MarkerId i, MarkerId j,
                           std::shared_ptr<const ForceElement> element, int joint);

  Mechanism m_;
  bool built_{false};
};

}  // namespace flexrod::multibody
