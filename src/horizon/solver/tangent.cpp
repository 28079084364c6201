#include "horizon/solver/tangent.hpp"

#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "horizon/core/error.hpp"
#include "horizon/parallel/decomposition.hpp"
#include "horizon/solver/forces.hpp"

namespace horizon {

namespace {
// The rows a product computes (parallel/decomposition.hpp): when the run is split over
// ranks, the owned particles' rows, and for the inputs of those rows the active ones
// (owned + bond neighbours); otherwise every row, in index order.
struct RowSet {
  const std::vector<uint32_t>* list = nullptr;
  std::size_t count = 0;
  std::size_t operator[](std::size_t r) const { return list ? (*list)[r] : r; }
};
RowSet active_rowset(const System& s) {
  return s.decomposition ? RowSet{&s.active_rows, s.active_rows.size()} : RowSet{nullptr, s.particles.size()};
}
RowSet owned_rowset(const System& s) {
  return s.decomposition ? RowSet{&s.owned, s.owned.size()} : RowSet{nullptr, s.particles.size()};
}
}  // namespace

std::size_t Linearization::bytes() const {
  return n.size() * sizeof(Vec3) + (transverse.size() + axial.size() + weight.size()) * sizeof(double) +
         b.size() * sizeof(Vec3) + coupling.size() * sizeof(double);
}

Linearization linearize(const System& s) {
  const auto& P = s.particles;
  const auto& B = s.bonds;
  const auto& M = s.model;
  const std::size_t n = P.size(), nb = B.size();
  Linearization lin;
  lin.n.assign(nb, Vec3{});
  lin.transverse.assign(nb, 0);
  lin.axial.assign(nb, 0);
  lin.weight.assign(nb, 0);
  lin.b.assign(n, Vec3{});
  lin.coupling.assign(n, 0);
  lin.state_based = M.state_based;
  // Split over ranks: the active rows (owned and their bond neighbours), enough for the
  // owned rows of the product and of the diagonal (TangentOperator).
  const RowSet rows_a = active_rowset(s);

  // P_i = a_i theta_i from the current displacements over the intact bonds, exactly as
  // the force pass computes it (seed 003 eq. 113; solver/forces.cpp).
  std::vector<double> Pc(n, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t ra = 0; ra < rows_a.count; ++ra) {
    const std::size_t i = rows_a[ra];
    if (M.dilatation_coef[i] == 0) continue;
    const Vec3 yi = P.X[i] + P.u[i];
    double sum = 0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      const double L = B.length[k];
      sum += B.weight[k] * B.volume[k] * L * (norm(P.X[j] + P.u[j] - yi) - L);
    }
    const double a = M.dilatation_coef[i] - M.deviatoric_coef[i] / M.dim;
    Pc[i] = a * M.dim * sum / M.weighted_volume[i];
    lin.coupling[i] = a * M.dim / M.weighted_volume[i];
  }

#pragma omp parallel for schedule(static)
  for (std::size_t ra = 0; ra < rows_a.count; ++ra) {
    const std::size_t i = rows_a[ra];
    const Vec3 yi = P.X[i] + P.u[i];
    Vec3 bi;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      if (!B.intact[k]) continue;
      const uint32_t j = B.nbr[k];
      const Vec3 Y = P.X[j] + P.u[j] - yi;
      const double y = norm(Y), L = B.length[k], e = y - L;
      const double wv = B.weight[k] * B.volume[k];
      const double tau = Pc[i] * L + M.deviatoric_coef[i] * e + M.pair_coef[i] / L * e + Pc[j] * L +
                         M.deviatoric_coef[j] * e + M.pair_coef[j] / L * e;
      const Vec3 nk = Y / y;
      lin.n[k] = nk;
      lin.transverse[k] = wv * tau / y;
      lin.axial[k] = wv * (M.deviatoric_coef[i] + M.deviatoric_coef[j] + (M.pair_coef[i] + M.pair_coef[j]) / L);
      lin.weight[k] = wv * L;
      bi += nk * lin.weight[k];
    }
    lin.b[i] = bi;
  }
  return lin;
}

namespace {

using Mat3 = Eigen::Matrix3d;

inline Eigen::Vector3d ev(const Vec3& v) { return {v.x, v.y, v.z}; }

// Per-thread sparse accumulator of one block row: column particle -> 3x3 block.
struct RowAccumulator {
  std::vector<int32_t> slot;
  std::vector<uint32_t> cols;
  std::vector<Mat3> blocks;

  explicit RowAccumulator(std::size_t n) : slot(n, -1) {}
  Mat3& at(uint32_t c) {
    int32_t& s = slot[c];
    if (s < 0) {
      s = static_cast<int32_t>(cols.size());
      cols.push_back(c);
      blocks.push_back(Mat3::Zero());
    }
    return blocks[static_cast<std::size_t>(s)];
  }
  void mark(uint32_t c) {
    if (slot[c] < 0) {
      slot[c] = static_cast<int32_t>(cols.size());
      cols.push_back(c);
    }
  }
  void clear() {
    for (uint32_t c : cols) slot[c] = -1;
    cols.clear();
    blocks.clear();
  }
};

// The column particles of block row i: i, its family, and (state-based neighbours) their
// families.
void mark_columns(const System& s, const Linearization& lin, std::size_t i, RowAccumulator& acc) {
  const auto& B = s.bonds;
  acc.mark(static_cast<uint32_t>(i));
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const uint32_t j = B.nbr[k];
    acc.mark(j);
    if (lin.coupling[j] == 0) continue;
    for (uint64_t q = B.begin(j); q < B.end(j); ++q)
      if (B.intact[q]) acc.mark(B.nbr[q]);
  }
}

// The blocks of row i of dF/du (the tangent is its negative), from the formulas in the header.
void row_blocks(const System& s, const Linearization& lin, std::size_t i, RowAccumulator& acc) {
  const auto& B = s.bonds;
  const double Vi = s.particles.volume[i];
  acc.at(static_cast<uint32_t>(i));  // the diagonal block, present even without bonds
  const Eigen::Vector3d bi = ev(lin.b[i]);
  const double ci = lin.coupling[i];
  for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
    if (!B.intact[k]) continue;
    const uint32_t j = B.nbr[k];
    const Eigen::Vector3d nk = ev(lin.n[k]);
    const Mat3 nn = nk * nk.transpose();
    const Mat3 D = Vi * (lin.transverse[k] * (Mat3::Identity() - nn) + lin.axial[k] * nn);
    acc.at(j) += D;
    acc.at(static_cast<uint32_t>(i)) -= D;
    if (ci != 0) {
      // V_i b_i (x) dP_i/du: dP_i/du_j = c_i w_k n_k, dP_i/du_i = -c_i b_i.
      acc.at(j) += (Vi * ci * lin.weight[k]) * bi * nk.transpose();
    }
    const double cj = lin.coupling[j];
    if (cj != 0) {
      // V_i w_k n_k (x) dP_j/du: dP_j/du_l = c_j w_q n_q (bond q: j->l), dP_j/du_j = -c_j b_j.
      const Eigen::Vector3d wv = (Vi * lin.weight[k] * cj) * nk;
      acc.at(j) -= wv * ev(lin.b[j]).transpose();
      for (uint64_t q = B.begin(j); q < B.end(j); ++q) {
        if (!B.intact[q]) continue;
        acc.at(B.nbr[q]) += (wv * lin.weight[q]) * ev(lin.n[q]).transpose();
      }
    }
  }
  if (ci != 0) acc.at(static_cast<uint32_t>(i)) -= (Vi * ci) * bi * bi.transpose();
}

}  // namespace

namespace {

std::vector<int> free_counts(const System& s, const DofMap& d) {
  std::vector<int> free_count(s.particles.size(), 0);
  for (std::size_t i = 0; i < free_count.size(); ++i)
    for (int c = 0; c < 3; ++c) free_count[i] += d.dof(i, c) >= 0;
  return free_count;
}

// Pass 1 of the assembly: the number of entries of each dof row of particle i.
std::vector<int64_t> row_counts(const System& s, const Linearization& lin, const std::vector<int>& free_count) {
  const std::size_t n = s.particles.size();
  std::vector<int64_t> row_nnz(n, 0);
#pragma omp parallel
  {
    RowAccumulator acc(n);
#pragma omp for schedule(dynamic, 64)
    for (std::size_t i = 0; i < n; ++i) {
      if (free_count[i] == 0) continue;
      mark_columns(s, lin, i, acc);
      int64_t count = 0;
      for (uint32_t c : acc.cols) count += free_count[c];
      row_nnz[i] = count;
      acc.clear();
    }
  }
  return row_nnz;
}

}  // namespace

int64_t tangent_nonzeros(const System& s, const DofMap& d, const Linearization& lin) {
  const std::vector<int> free_count = free_counts(s, d);
  const std::vector<int64_t> row_nnz = row_counts(s, lin, free_count);
  int64_t nnz = 0;
  for (std::size_t i = 0; i < row_nnz.size(); ++i) nnz += row_nnz[i] * free_count[i];
  return nnz;
}

SparseMatrix assemble_tangent(const System& s, const DofMap& d, const Linearization& lin) {
  const std::size_t n = s.particles.size();
  const auto N = static_cast<int>(d.size());
  const std::vector<int> free_count = free_counts(s, d);
  const std::vector<int64_t> row_nnz = row_counts(s, lin, free_count);
  SparseMatrix K(N, N);
  std::vector<int64_t> start(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) start[i + 1] = start[i] + row_nnz[i] * free_count[i];
  const int64_t nnz = start[n];
  if (nnz > std::numeric_limits<int>::max())
    throw Error("the assembled tangent would hold " + std::to_string(nnz) +
                " entries, more than 32-bit indices allow; use solver.linear_solver: matrix_free");
  K.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = K.outerIndexPtr();
  for (std::size_t i = 0; i < n; ++i) {
    int r = 0;
    for (int c = 0; c < 3; ++c)
      if (d.dof(i, c) >= 0) outer[d.dof(i, c)] = static_cast<int>(start[i] + r++ * row_nnz[i]);
  }
  outer[N] = static_cast<int>(nnz);
  int* inner = K.innerIndexPtr();
  double* value = K.valuePtr();

  // Pass 2: the blocks, columns sorted, written as the dof rows' entries.
#pragma omp parallel
  {
    RowAccumulator acc(n);
    std::vector<int32_t> order;
#pragma omp for schedule(dynamic, 64)
    for (std::size_t i = 0; i < n; ++i) {
      if (free_count[i] == 0) continue;
      row_blocks(s, lin, i, acc);
      order.resize(acc.cols.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return acc.cols[a] < acc.cols[b]; });
      for (int r = 0; r < 3; ++r) {
        const int32_t row = d.dof(i, r);
        if (row < 0) continue;
        int64_t at = outer[row];
        for (int32_t o : order) {
          const uint32_t col = acc.cols[o];
          const Mat3& blk = acc.blocks[o];
          for (int c = 0; c < 3; ++c) {
            const int32_t dc = d.dof(col, c);
            if (dc < 0) continue;
            inner[at] = dc;
            value[at] = -blk(r, c);  // K = -dF/du
            ++at;
          }
        }
      }
      acc.clear();
    }
  }
  return K;
}

SparseMatrix assemble_tangent(const System& s, const DofMap& d) { return assemble_tangent(s, d, linearize(s)); }

SparseMatrix finite_difference_tangent(System& s, const DofMap& d, double probe) {
  auto& P = s.particles;
  const auto& B = s.bonds;
  const std::size_t n = P.size();
  if (probe <= 0) probe = 1e-6 * s.spacing;
  FixedBonds fixed(s);
  const std::vector<Vec3> u0 = P.u;
  const int hops = std::max(s.model.state_based ? 2 : 1, s.model.reach_hops);

  // Rows a probe of particle p reaches: p and everything within `hops` bonds.
  auto reached = [&](std::size_t p, std::vector<uint32_t>& out, std::vector<uint8_t>& seen) {
    out.assign(1, static_cast<uint32_t>(p));
    seen[p] = 1;
    std::size_t begin = 0;
    for (int h = 0; h < hops; ++h) {
      const std::size_t end = out.size();
      for (std::size_t a = begin; a < end; ++a)
        for (uint64_t k = B.begin(out[a]); k < B.end(out[a]); ++k)  // broken bonds too: some models keep them in compression
          if (!seen[B.nbr[k]]) {
            seen[B.nbr[k]] = 1;
            out.push_back(B.nbr[k]);
          }
      begin = end;
    }
    for (uint32_t q : out) seen[q] = 0;
  };

  // Colours: cells of width 2 * hops * (longest bond); particles in cells of the same
  // parity class are further apart than that, so their reached rows never overlap.
  double reach = 0;
  for (double L : B.length) reach = std::max(reach, L);
  const double cell = 2.0 * hops * reach * 1.001 + 1e-300;
  Vec3 lo{1e300, 1e300, 1e300};
  for (const auto& x : P.X)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], x[a]);
  std::vector<int64_t> key(n);
  std::vector<int> parity(n);
  for (std::size_t i = 0; i < n; ++i) {
    int64_t c[3];
    for (int a = 0; a < 3; ++a) c[a] = static_cast<int64_t>(std::floor((P.X[i][a] - lo[a]) / cell));
    key[i] = (c[0] * 1000003 + c[1]) * 1000003 + c[2];
    parity[i] = static_cast<int>((c[0] & 1) | ((c[1] & 1) << 1) | ((c[2] & 1) << 2));
  }
  std::vector<std::size_t> by_cell(n);
  std::iota(by_cell.begin(), by_cell.end(), 0);
  std::stable_sort(by_cell.begin(), by_cell.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  std::vector<int> rank(n, 0);
  int max_rank = 0;
  for (std::size_t a = 1; a < n; ++a)
    if (key[by_cell[a]] == key[by_cell[a - 1]]) {
      rank[by_cell[a]] = rank[by_cell[a - 1]] + 1;
      max_rank = std::max(max_rank, rank[by_cell[a]]);
    }
  const int colours = 8 * (max_rank + 1);
  std::vector<std::vector<uint32_t>> groups(static_cast<std::size_t>(colours));
  for (std::size_t i = 0; i < n; ++i) groups[static_cast<std::size_t>(parity[i] * (max_rank + 1) + rank[i])].push_back(static_cast<uint32_t>(i));

  std::vector<Eigen::Triplet<double, int>> triplets;
  std::vector<Vec3> f_plus(n);
  std::vector<uint32_t> rows;
  std::vector<uint8_t> seen(n, 0);
  for (const auto& group : groups) {
    if (group.empty()) continue;
    for (int c = 0; c < 3; ++c) {
      if (!s.active(c)) continue;
      bool any = false;
      for (uint32_t p : group) any = any || d.dof(p, c) >= 0;
      if (!any) continue;
      for (double sign : {1.0, -1.0}) {
        P.u = u0;
        for (uint32_t p : group)
          if (d.dof(p, c) >= 0) P.u[p][c] += sign * probe;
        compute_forces(s, false);
        if (sign > 0) f_plus = P.f;
      }
      for (uint32_t p : group) {
        const int32_t col = d.dof(p, c);
        if (col < 0) continue;
        reached(p, rows, seen);
        for (uint32_t i : rows)
          for (int r = 0; r < 3; ++r) {
            const int32_t row = d.dof(i, r);
            if (row < 0) continue;
            const double v = -(f_plus[i][r] - P.f[i][r]) / (2 * probe) * P.volume[i];
            if (v != 0) triplets.emplace_back(row, col, v);
          }
      }
    }
  }
  P.u = u0;
  compute_forces(s, false);
  SparseMatrix K(static_cast<int>(d.size()), static_cast<int>(d.size()));
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

TangentOperator::TangentOperator(const System& s, const DofMap& d)
    : s_(s), d_(d), lin_(linearize(s)), x3_(s.particles.size()), dP_(s.particles.size(), 0) {}

void TangentOperator::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const auto& P = s_.particles;
  const auto& B = s_.bonds;
  const RowSet rows_a = active_rowset(s_), rows_o = owned_rowset(s_);
  std::fill(x3_.begin(), x3_.end(), Vec3{});
  for (std::size_t k = 0; k < d_.size(); ++k) x3_[d_.particle[k]][d_.component[k]] = x[static_cast<Eigen::Index>(k)];
  // Split over ranks: x holds the owned dofs; the ghosts' entries come from their owners.
  if (s_.decomposition) exchange_ghost_values(*s_.decomposition, x3_);
  if (lin_.state_based) {
#pragma omp parallel for schedule(static)
    for (std::size_t ra = 0; ra < rows_a.count; ++ra) {
      const std::size_t i = rows_a[ra];
      const double ci = lin_.coupling[i];
      if (ci == 0) {
        dP_[i] = 0;
        continue;
      }
      double sum = 0;
      for (uint64_t k = B.begin(i); k < B.end(i); ++k)
        sum += lin_.weight[k] * dot(lin_.n[k], x3_[B.nbr[k]] - x3_[i]);
      dP_[i] = ci * sum;
    }
  }
  y.resize(static_cast<Eigen::Index>(d_.size()));
  if (s_.decomposition) y.setZero();  // the dofs of other ranks' particles
#pragma omp parallel for schedule(static)
  for (std::size_t ra = 0; ra < rows_o.count; ++ra) {
    const std::size_t i = rows_o[ra];
    const int32_t d0 = d_.dof(i, 0), d1 = d_.dof(i, 1), d2 = d_.dof(i, 2);
    if (d0 < 0 && d1 < 0 && d2 < 0) continue;
    Vec3 f;
    const double dPi = lin_.state_based ? dP_[i] : 0.0;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const Vec3& nk = lin_.n[k];
      const Vec3 dY = x3_[B.nbr[k]] - x3_[i];
      const double along = dot(nk, dY);
      double axial = (lin_.axial[k] - lin_.transverse[k]) * along;
      if (lin_.state_based) axial += lin_.weight[k] * (dPi + dP_[B.nbr[k]]);
      f += dY * lin_.transverse[k] + nk * axial;
    }
    const double Vi = P.volume[i];
    if (d0 >= 0) y[d0] = -Vi * f.x;
    if (d1 >= 0) y[d1] = -Vi * f.y;
    if (d2 >= 0) y[d2] = -Vi * f.z;
  }
}

Eigen::VectorXd TangentOperator::diagonal() const {
  const auto& P = s_.particles;
  const auto& B = s_.bonds;
  const RowSet rows_o = owned_rowset(s_);
  std::vector<uint64_t> rev;
  // Local rows (parallel/decomposition.hpp): rows beyond the active ones are empty here;
  // an owned row's neighbours are active, so its bonds' reverses are the whole system's.
  if (lin_.state_based) rev = reverse_bonds(B, s_.decomposition && s_.decomposition->local_rows);
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(d_.size()));
#pragma omp parallel for schedule(static)
  for (std::size_t ra = 0; ra < rows_o.count; ++ra) {
    const std::size_t i = rows_o[ra];
    Vec3 g;
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const Vec3& nk = lin_.n[k];
      double along = lin_.axial[k] - lin_.transverse[k];
      if (lin_.state_based) along += lin_.coupling[B.nbr[k]] * lin_.weight[k] * lin_.weight[rev[k]];
      for (int c = 0; c < 3; ++c) g[c] += lin_.transverse[k] + along * nk[c] * nk[c];
    }
    for (int c = 0; c < 3; ++c) {
      const int32_t dc = d_.dof(i, c);
      if (dc < 0) continue;
      diag[dc] = P.volume[i] * (g[c] + lin_.coupling[i] * lin_.b[i][c] * lin_.b[i][c]);
    }
  }
  return diag;
}

Eigen::VectorXd stiffness_row_bound(const System& s, const DofMap& d, const Linearization& lin) {
  const auto& B = s.bonds;
  const std::size_t n = s.particles.size();
  const int dim = s.dimension;
  auto norm1 = [dim](const Vec3& v) {
    double a = 0;
    for (int c = 0; c < dim; ++c) a += std::abs(v[c]);
    return a;
  };
  const RowSet rows_a = active_rowset(s), rows_o = owned_rowset(s);
  // G_j bounds sum_l |dP_j/du_l| (all components).
  std::vector<double> G(n, 0);
  if (lin.state_based) {
#pragma omp parallel for schedule(static)
    for (std::size_t ra = 0; ra < rows_a.count; ++ra) {
      const std::size_t j = rows_a[ra];
      if (lin.coupling[j] == 0) continue;
      double sum = norm1(lin.b[j]);
      for (uint64_t q = B.begin(j); q < B.end(j); ++q) sum += lin.weight[q] * norm1(lin.n[q]);
      G[j] = std::abs(lin.coupling[j]) * sum;
    }
  }
  Eigen::VectorXd bound = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(d.size()));
#pragma omp parallel for schedule(static)
  for (std::size_t ra = 0; ra < rows_o.count; ++ra) {
    const std::size_t i = rows_o[ra];
    double row[3] = {0, 0, 0};
    for (uint64_t k = B.begin(i); k < B.end(i); ++k) {
      const Vec3& nk = lin.n[k];
      const double T = lin.transverse[k], A = lin.axial[k];
      const double Gj = lin.state_based ? G[B.nbr[k]] : 0.0;
      for (int r = 0; r < dim; ++r) {
        double a = 0;
        for (int c = 0; c < dim; ++c) a += std::abs(T * ((r == c) - nk[r] * nk[c]) + A * nk[r] * nk[c]);
        row[r] += 2 * a + lin.weight[k] * std::abs(nk[r]) * Gj;
      }
    }
    for (int r = 0; r < dim; ++r) {
      const int32_t dr = d.dof(i, r);
      if (dr < 0) continue;
      bound[dr] = row[r] + (lin.state_based ? std::abs(lin.b[i][r]) * G[i] : 0.0);
    }
  }
  return bound;
}

Eigen::VectorXd row_abs_sums(const System& s, const DofMap& d, const SparseMatrix& K) {
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(K.rows());
  for (int c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it) rows[it.row()] += std::abs(it.value());
  for (std::size_t k = 0; k < d.size(); ++k) rows[static_cast<Eigen::Index>(k)] /= s.particles.volume[d.particle[k]];
  return rows;
}

namespace {
double round_off_from_bound(const System& s, const DofMap& d, const Eigen::VectorXd& bound) {
  double xmax = 0;
  for (const auto& x : s.particles.X) xmax = std::max({xmax, std::abs(x.x), std::abs(x.y), std::abs(x.z)});
  if (s.decomposition) {  // the owned dofs' bounds (the others are not computed here)
    Eigen::VectorXd r(static_cast<Eigen::Index>(d.size()));
    for (std::size_t k = 0; k < d.size(); ++k)
      r[static_cast<Eigen::Index>(k)] = bound[static_cast<Eigen::Index>(k)] * s.particles.volume[d.particle[k]];
    return std::numeric_limits<double>::epsilon() * xmax * dof_norm(s, d, r);
  }
  double sum = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const double r = bound[static_cast<Eigen::Index>(k)] * s.particles.volume[d.particle[k]];
    sum += r * r;
  }
  return std::numeric_limits<double>::epsilon() * xmax * std::sqrt(sum);
}
}  // namespace

double round_off_residual(const System& s, const DofMap& d, const Linearization& lin) {
  return round_off_from_bound(s, d, stiffness_row_bound(s, d, lin));
}

double round_off_residual(const System& s, const DofMap& d, const SparseMatrix& K) {
  return round_off_from_bound(s, d, row_abs_sums(s, d, K));
}

}  // namespace horizon

namespace horizon {

bool model_tangent(const System& s, const DofMap& d, SparseMatrix& K) {
  StiffnessSink sink;
  sink.dof = d.index.data();
  // The owner of the force pass, or a model whose stiffness covers the whole system (the
  // correspondence model when it holds every particle).
  bool have = false;
  if (const Model* owner = s.models.owner()) {
    have = owner->stiffness(s, sink);
  } else {
    for (const auto& m : s.models)
      if ((have = m->stiffness(s, sink))) break;
  }
  if (!have) return false;
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(sink.entries.size());
  for (const StiffnessEntry& e : sink.entries) triplets.emplace_back(e.row, e.col, e.value);
  K = SparseMatrix(static_cast<int>(d.size()), static_cast<int>(d.size()));
  K.setFromTriplets(triplets.begin(), triplets.end());
  return true;
}

int hold_loose_dofs(SparseMatrix& K) {
  const Eigen::Index n = K.cols();
  std::vector<uint8_t> stiff(static_cast<std::size_t>(n), 0);
  double diag_sum = 0;
  Eigen::Index diag_count = 0;
  for (Eigen::Index c = 0; c < K.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(K, c); it; ++it) {
      if (it.value() == 0) continue;
      stiff[static_cast<std::size_t>(c)] = 1;
      if (it.row() == c) {
        diag_sum += std::abs(it.value());
        ++diag_count;
      }
    }
  const double fill = diag_count > 0 ? diag_sum / static_cast<double>(diag_count) : 1.0;
  int loose = 0;
  for (Eigen::Index c = 0; c < n; ++c)
    if (!stiff[static_cast<std::size_t>(c)]) {
      K.coeffRef(c, c) = fill;
      ++loose;
    }
  if (loose) K.makeCompressed();
  return loose;
}

SparseMatrix solver_tangent(System& s, const DofMap& d, TangentKind kind) {
  SparseMatrix K;
  if (kind == TangentKind::analytic && unified_form(s)) {
    K = assemble_tangent(s, d);
  } else if (!(kind == TangentKind::analytic && model_tangent(s, d, K))) {
    K = finite_difference_tangent(s, d);
  }
  hold_loose_dofs(K);
  return K;
}

}  // namespace horizon
