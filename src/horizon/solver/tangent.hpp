#pragma once
// The tangent stiffness K = -dF/du of the internal nodal forces F_i = f_i V_i, on the free
// dofs, for the unified bond force form of state/system.hpp:
//   F_i = V_i sum_k omega v (tau_i + tau_j) n,  tau_i = P_i L + Q_i e + R_i e/L,  n = Y/|Y|.
// Differentiating (product rule on g n with g = omega v (tau_i + tau_j)):
//   dF_i = V_i sum_k [ T_k (I - n n^T) dY + A_k n (n . dY) + w_k n (dP_i + dP_j) ],
//   T_k = omega v (tau_i + tau_j)/|Y|        (the geometric, transverse stiffness),
//   A_k = omega v (Q_i + Q_j + (R_i + R_j)/L) (the axial stiffness),
//   w_k = omega v L,                          (the bond's weight in theta and in dF/dP)
//   dP_i = c_i sum_k w_k n . dY,  c_i = a_i d/m_i,  a_i = d k'/m_i - alpha mu/(d m_i),
// since P_i = a_i theta_i and theta_i = (d/m_i) sum_k omega v L e (seed 003 eq. 113,
// digest sec. 8-9; docs/models.md sec. 1). dY = du_j - du_i. The dP_j term couples i
// to the family of each neighbour j: a state-based tangent reaches two horizons (Parks,
// digest 004 sec. 10.7). Bond-based particles have c_i = 0 and couple within one
// horizon. The form derives from the energy sum_i W_i V_i, so K is symmetric.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "horizon/family/bond_helpers.hpp"
#include "horizon/solver/equilibrium.hpp"
#include "horizon/solver/build.hpp"

namespace horizon {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// The linearisation of the internal forces at the current displacements, bond by bond
// (broken bonds have zero coefficients). Built in O(bonds); from it come the assembled
// tangent, the matrix-free product and the ADR stiffness bound.
struct Linearization {
  std::vector<Vec3> n;              // per bond: deformed direction Y/|Y|
  std::vector<double> transverse;   // per bond: T_k
  std::vector<double> axial;        // per bond: A_k
  std::vector<double> weight;       // per bond: w_k
  std::vector<Vec3> b;              // per particle: sum_k w_k n_k  (= dP_i/d(-u_i) / c_i)
  std::vector<double> coupling;     // per particle: c_i
  bool state_based = false;
  std::size_t bytes() const;
};
Linearization linearize(const System& s);

// The assembled tangent on the free dofs. Row-block i is computed from i's bonds (and,
// for state-based particles, their neighbours' bonds) and stored as column i of a
// column-major matrix, i.e. the matrix holds K^T, equal to K (symmetric) to round-off.
SparseMatrix assemble_tangent(const System& s, const DofMap& d, const Linearization& lin);
SparseMatrix assemble_tangent(const System& s, const DofMap& d);
// The number of entries the assembled tangent would hold (its first pass only).
int64_t tangent_nonzeros(const System& s, const DofMap& d, const Linearization& lin);

// The tangent by central finite differences of compute_forces (any material): columns
// whose rows cannot overlap are probed together (particles more than twice the reach of
// a perturbation apart share a probe). Bonds do not break while probing; u and the
// forces are restored. probe: the displacement step [m] (default 1e-6 spacing).
SparseMatrix finite_difference_tangent(System& s, const DofMap& d, double probe = 0);

// The analytic tangent of the model that owns the force pass, or of a model that holds
// every particle (Model::stiffness; the correspondence model), at the current
// displacements: false when there is no such model or it has none.
bool model_tangent(const System& s, const DofMap& d, SparseMatrix& K);

// The assembled tangent a static or implicit solver uses: the unified analytic one, the
// owning model's analytic one, or finite differences (kind finite_difference, or a model
// without an analytic tangent). Held loose dofs (hold_loose_dofs) in all cases.
SparseMatrix solver_tangent(System& s, const DofMap& d, TangentKind kind);

// Unknowns without stiffness: a dof whose tangent row is empty belongs to a node that no
// intact bond or bond pair holds any more (a fragment cut loose by failure; in the
// transverse mode of a plate, a node all of whose pairs failed). Such a row gets a
// diagonal entry equal to the mean diagonal of K, so that the factorisation and CG stay
// defined and the Newton step leaves the node where it is when nothing loads it.
// Returns the number of such dofs.
int hold_loose_dofs(SparseMatrix& K);

// y = K x without assembling K: two passes over the bonds, like compute_forces. Split
// over MPI ranks (parallel/decomposition.hpp), x holds the owned dofs, the ghosts'
// entries are exchanged first and y gets the owned rows (the others 0), each row with
// the serial row's bits.
class TangentOperator {
 public:
  TangentOperator(const System& s, const DofMap& d);
  Eigen::Index rows() const { return static_cast<Eigen::Index>(d_.size()); }
  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // Diagonal of K (for a Jacobi preconditioner).
  Eigen::VectorXd diagonal() const;
  std::size_t bytes() const { return lin_.bytes(); }
  const System& system() const { return s_; }
  const DofMap& dofs() const { return d_; }

 private:
  const System& s_;
  const DofMap& d_;
  Linearization lin_;
  mutable std::vector<Vec3> x3_;   // x scattered to particles
  mutable std::vector<double> dP_;
};

// Gerschgorin bound sum_j |K_ij| / V_i of every dof row (force-density units), from
// the triangle inequality on the terms above: an upper bound of the row sums of the
// tangent at the current state, computed in O(bonds). ADR's fictitious mass uses it.
Eigen::VectorXd stiffness_row_bound(const System& s, const DofMap& d, const Linearization& lin);

// The residual norm that round-off alone leaves: positions are known to eps |X|, so a
// force carries an error of about eps |X|_max sum_j |K_ij| (in nodal units); the norm
// of those over the free dofs. Solvers accept a residual below it as converged, so that
// a tolerance relative to a tiny load (or a tight tolerance) cannot ask for more digits
// than the forces have.
double round_off_residual(const System& s, const DofMap& d, const Linearization& lin);
// The same from an assembled tangent's row sums (any model).
double round_off_residual(const System& s, const DofMap& d, const SparseMatrix& K);
// Row sums sum_j |K_ij| / V_i of an assembled tangent (force-density units), per dof.
Eigen::VectorXd row_abs_sums(const System& s, const DofMap& d, const SparseMatrix& K);

}  // namespace horizon
