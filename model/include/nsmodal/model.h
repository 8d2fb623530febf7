#pragma once
// The vibro-impact model: M xdd + C xd + K x = f0 + f cos(w t) in free flight
// (C = 0, f0 = f = 0 in the paper: M xdd + K x = 0) and K >= 1 unilateral
// contacts, each with a Newton impact law.
//
// Contact j (numbered from 1 in files and messages) has the gap
//   g_j(x) = d_j - n_j . x >= 0          (Signorini; paper eq. 1 is n = e_c)
// with a fixed normal n_j and d_j > 0 (the rest position x = 0 is clear of
// every wall). Impact law (paper eq. 2b generalised to any SPD M and any
// normal): the impulse acts along M^-1 n_j, M (v+ - v-) = n_j Lambda, with
// Lambda chosen so that
//   n_j . v(t+) = -e_j n_j . v(t-),   0 <= e_j <= 1.
// For a dof contact (n = e_c) and a diagonal M this changes v_c only ("other
// velocities continuous"); for a coupled M it is the only choice that
// conserves energy at e = 1. Several contacts struck at once: sim/'s
// contact.h states the law.
#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

namespace nsmodal {

// External forces f0 + f cos(w t) on the dofs (scene table [forcing]).
// An empty vector means no such force.
struct Forcing {
  Eigen::VectorXd constant;   // f0: a constant force (preload, gravity), length N or empty
  Eigen::VectorXd amplitude;  // f: amplitude of the harmonic force, length N or empty
  double frequency = 0.0;     // w in rad/s, > 0 when f is given

  bool HasConstant() const { return constant.size() > 0 && constant.cwiseAbs().maxCoeff() > 0.0; }
  bool HasHarmonic() const { return amplitude.size() > 0 && amplitude.cwiseAbs().maxCoeff() > 0.0; }
};

// One contact, as written in a scene ([[contact]] tables, or the [system]
// shorthand contact_dof, gap, restitution for one upper stop).
struct Contact {
  enum class Form {
    kDof,      // x_dof <= d (upper) or x_dof >= -d (lower): n = +-e_dof
    kBetween,  // x_dof - x_other <= d: a relative contact, n = e_dof - e_other
    kNormal,   // n . x <= d for a given n
  };
  Form form = Form::kDof;
  int dof = 0;          // kDof: the dof; kBetween: the first of the pair (0-based)
  int other = -1;       // kBetween: the second dof of the pair
  bool upper = true;    // kDof: the wall above (x <= d) or below (x >= -d)
  Eigen::VectorXd normal;    // n, length N (built by the makers below)
  double gap = 1.0;          // d > 0
  double restitution = 1.0;  // e in [0, 1]
  bool shorthand = false;    // written as [system]'s keys: its fields are named system.gap, ...

  // n . y for a vector of positions or velocities y: for the dof and between
  // forms without products (exactly y_c, -y_c or y_a - y_b).
  double Along(const Eigen::Ref<const Eigen::VectorXd>& y) const {
    switch (form) {
      case Form::kDof: return upper ? y[dof] : -y[dof];
      case Form::kBetween: return y[dof] - y[other];
      case Form::kNormal: break;
    }
    return normal.dot(y);
  }
  // n' A for a matrix A with N rows (Phi, M^-1 K, ...): A's rows for those forms.
  Eigen::RowVectorXd RowOf(const Eigen::Ref<const Eigen::MatrixXd>& a) const;
  // "x2 <= 1", "x2 >= -1", "x1 - x2 <= 0.2", "n . x <= 1".
  std::string Describe() const;
  // The dof its figures show: the dof, the first of a pair, the largest |n_i|.
  int PlotDof() const;
};

// The contact makers (n: the number of dofs). Checks are Validate's.
Contact DofContact(int n, int dof, bool upper, double gap, double restitution);
Contact BetweenContact(int n, int dof, int other, double gap, double restitution);
Contact NormalContact(Eigen::VectorXd normal, double gap, double restitution);

struct ModelSource;  // model_spec.h: the keys a model was assembled from

struct Model {
  Eigen::MatrixXd mass;       // M, symmetric positive definite, N x N
  Eigen::MatrixXd stiffness;  // K, symmetric positive semi-definite, N x N (zero
                              // eigenvalues: rigid-body modes, undamped and unforced only)
  Eigen::MatrixXd damping;    // C, symmetric positive semi-definite N x N, or empty (none)
  Forcing forcing;            // none by default
  std::vector<Contact> contacts;  // at least one; contact j + 1 of the files is contacts[j]
  // The keys it was assembled from (AssembleModel; null for a model built in
  // code or unpickled): parameter.h rebuilds the model from them at another
  // value. Code that edits a model in place drops them (source.reset()):
  // they would rebuild the model before the edit.
  std::shared_ptr<const ModelSource> source;

  int dofs() const { return static_cast<int>(mass.rows()); }
  bool HasDamping() const { return damping.size() > 0 && damping.cwiseAbs().maxCoeff() > 0.0; }
  // C, f0 and f as full-size values (zero where absent).
  Eigen::MatrixXd DampingMatrix() const {
    return damping.size() > 0 ? damping : Eigen::MatrixXd::Zero(dofs(), dofs());
  }
  Eigen::VectorXd ConstantForce() const {
    return forcing.constant.size() > 0 ? forcing.constant : Eigen::VectorXd::Zero(dofs());
  }
  Eigen::VectorXd ForceAmplitude() const {
    return forcing.amplitude.size() > 0 ? forcing.amplitude : Eigen::VectorXd::Zero(dofs());
  }
  // No damping and no force: the paper's system, whose energy flight conserves.
  bool Conservative() const { return !HasDamping() && !forcing.HasConstant() && !forcing.HasHarmonic(); }
  int NumContacts() const { return static_cast<int>(contacts.size()); }
  // Contact 1: the one-contact analysis's (paper sections 1-4; RequireOneContact).
  const Contact& FirstContact() const { return contacts.front(); }
  Contact& FirstContact() { return contacts.front(); }
  // Every contact's restitution equal to e.
  bool AllRestitution(double e) const;
};

// The field of contact j (0-based) a message names: "contact[2].gap" (1-based,
// as the scene's [[contact]] tables), or "system.gap" for the shorthand.
std::string ContactField(const Contact& contact, int j, const std::string& field);

// The one-contact analyses (the paper's, the forced responses) refuse a model
// with several contacts: InputError naming "contact" and what was asked.
void RequireOneContact(const Model& model, const std::string& what);

// E = v' M v / 2 + x' K x / 2 of the physical state z = (x, v).
double MechanicalEnergy(const Model& model, const Eigen::VectorXd& z);

// Damping matrices from the usual engineering forms (scene keys in scene.h).
// Rayleigh: C = a M + b K, a, b >= 0 (field "system.rayleigh_damping").
Eigen::MatrixXd RayleighDamping(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness, double a, double b);
// Modal: C = M Phi diag(2 zeta_i w_i) Phi' M with Phi' M Phi = I, the linear
// modes in ascending frequency; one zeta_i >= 0 per mode ("system.damping_ratios").
Eigen::MatrixXd ModalDamping(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& stiffness,
                             const std::vector<double>& ratios);

// A chain ground - k1 - m1 - k2 - m2 - ... (the paper's Figure 1 for N = 2).
// springs[0] links the ground to m1, springs[i] links m_i to m_{i+1}.
// Throws InputError naming "system.masses" or "system.springs" on bad values.
Model MakeChain(const std::vector<double>& masses, const std::vector<double>& springs,
                int contact, double gap, double restitution);

// A uniform elastic bar in axial vibration by linear finite elements (scene
// key [system] bar, issue 12): `elements` elements of length h = L / n, one
// node at each element end, stiffness E A / h [1 -1; -1 1] and mass
// rho A h / 6 [2 1; 1 2] (consistent) or rho A h / 2 [1 0; 0 1] (lumped) per
// element. fixed-free: node 0 clamped, dofs = nodes 1..n (positive definite);
// free-free: dofs = nodes 0..n, K has the rigid-body mode (1, ..., 1).
// The contact is on `contact` (0-based dof). Throws InputError naming
// system.bar.<field> and the value on bad input.
struct BarSpec {
  enum class Boundary { kFixedFree, kFreeFree };
  enum class MassForm { kConsistent, kLumped };
  double length = 1.0;          // L (m)
  double youngs_modulus = 1.0;  // E (Pa)
  double density = 1.0;         // rho (kg/m^3)
  double area = 1.0;            // A (m^2)
  int elements = 1;             // n
  Boundary boundary = Boundary::kFixedFree;
  MassForm mass = MassForm::kConsistent;
  int Dofs() const { return boundary == Boundary::kFixedFree ? elements : elements + 1; }
  double WaveSpeed() const;     // c = sqrt(E / rho)
};
Model MakeBar(const BarSpec& bar, int contact, double gap, double restitution);
// "fixed-free" | "free-free" and "consistent" | "lumped"; throws InputError
// naming `field` and the text otherwise.
BarSpec::Boundary ParseBarBoundary(const std::string& text, const std::string& field = "system.bar.boundary");
BarSpec::MassForm ParseBarMass(const std::string& text, const std::string& field = "system.bar.mass");

// The paper's default system: m1 = m2 = 1, k1 = 0.85, k2 = 2, d = 1, e = 1, c = x2.
Model PaperModel();

// Scales nsmodal honours, checked by Validate and MakeModalBasis:
//   the eigenvalues of M, and those of K, span at most kMaxCondition (a
//   nearly singular matrix leaves no digits in M^-1 K);
//   the linear frequencies span at most kMaxFrequencyRatio (the exact flight
//   and the guaranteed impact search step at the fastest mode's scale over the
//   slowest one's periods);
//   the energy scale K d^2 / 2 lies within [1 / kMaxEnergyScale, kMaxEnergyScale].
//   at most kMaxDofs degrees of freedom (dense N x N matrices and O(N^3)
//   eigen-decompositions: 2000 dofs take 32 MB a matrix and seconds).
inline constexpr int kMaxDofs = 2000;
inline constexpr double kMaxCondition = 1e12;
inline constexpr double kMaxFrequencyRatio = 1e6;
inline constexpr double kMaxEnergyScale = 1e200;
// An eigenvalue of K at most kRigidBodyTolerance times the largest (either
// sign) is a rigid-body mode: zero frequency, a free drift. Round-off leaves
// the zero eigenvalue of an assembled singular K within ~1e-16 of the largest
// (measured: free-free bars and chains of 2 to 2,000 dofs); the other
// eigenvalues must stay above 1 / kMaxCondition of the largest, and those in
// between are refused as too close to singular.
inline constexpr double kRigidBodyTolerance = 1e-14;

// The eigenvalues of a symmetric matrix, ascending. A tridiagonal one (every
// chain's and bar's M, K and Rayleigh C) takes the tridiagonal QR iteration,
// O(N^2), instead of the dense reduction's O(N^3). No checks: Validate's.
Eigen::VectorXd SymmetricEigenvalues(const Eigen::MatrixXd& a);

// The number of rigid-body modes of a symmetric stiffness (its eigenvalues
// within kRigidBodyTolerance of zero). No checks: Validate's.
int RigidBodyModes(const Eigen::MatrixXd& stiffness);


// Checks every field and the scales above; throws InputError naming the field
// ("system.mass_matrix", "system.contact_dof", "system.gap",
// "system.restitution", "contact[j].normal", "contact[j].gap", ...,
// "system.damping_matrix", "forcing.amplitude",
// "forcing.frequency", ...) and the value. The damping must be symmetric
// positive semi-definite (a negative eigenvalue would feed energy in); so
// must the stiffness, nonzero, and with rigid-body modes (zero eigenvalues)
// only for an undamped, unforced model (the free drift is flown in closed
// form; damping and forcing need the static and harmonic responses, K^-1); a
// harmonic force needs w > 0 within kMaxFrequencyRatio of the linear
// frequencies. Contacts: each normal of length N, finite and nonzero, each
// gap positive, each restitution in [0, 1]; two contacts with the same normal
// direction are refused (one wall would hide the other: a duplicate), and so
// are opposing walls that leave no room between them (the clearance
// d_j / |n_j| + d_k / |n_k| below 1e-12 of the gaps). Returns the number of
// rigid-body modes (RigidBodyModes of K,
// from the eigenvalues the checks computed).
int Validate(const Model& model);

// Numbers in messages: a value as given (17 significant digits) and an
// estimate or a measure (3 significant digits, "%.3g").
std::string FormatValue(double v);
std::string FormatEstimate(double v);

}  // namespace nsmodal
