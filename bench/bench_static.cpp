// Memory of the tangent and the cost of a direct solve for a deck, without solving:
// the entries of the assembled tangent (bytes per bond), and (--analyze) CHOLMOD's
// symbolic analysis of it: the entries of the Cholesky factor and the flop count of the
// factorisation. bench/static/run.sh uses it for docs/benchmarks.md, "Static solvers".
//   bench_static deck.yaml [--analyze]
#include <fmt/format.h>

#include <Eigen/CholmodSupport>
#include <chrono>
#include <cstring>

#include "horizon/deck/deck.hpp"
#include "horizon/loading/loads.hpp"
#include "horizon/solver/equilibrium.hpp"
#include "horizon/solver/tangent.hpp"

int main(int argc, char** argv) {
  using namespace horizon;
  if (argc < 2) {
    fmt::print(stderr, "usage: bench_static deck.yaml [--analyze]\n");
    return 1;
  }
  const bool analyze = argc > 2 && std::strcmp(argv[2], "--analyze") == 0;
  const Config c = load_deck(argv[1]);
  System s = build_system(c);
  Loads loads(c, s);
  const DofMap d = make_dof_map(s, loads);
  const Linearization lin = linearize(s);
  const int64_t nnz = tangent_nonzeros(s, d, lin);
  const double bytes = static_cast<double>(nnz) * (sizeof(double) + sizeof(int)) + (d.size() + 1.0) * sizeof(int);
  const double bonds = static_cast<double>(s.bonds.size());
  fmt::print("particles {} bonds {} dofs {}\n", s.particles.size(), s.bonds.size(), d.size());
  fmt::print("tangent: {} entries, {:.3f} GB, {:.0f} B per bond, {:.0f} entries per dof row\n", nnz, bytes / 1e9,
             bytes / bonds, static_cast<double>(nnz) / static_cast<double>(d.size()));
  fmt::print("matrix-free operator: {:.0f} B per bond\n", static_cast<double>(lin.bytes()) / bonds);
  if (analyze) {
    const auto t0 = std::chrono::steady_clock::now();
    const SparseMatrix K = assemble_tangent(s, d, lin);
    const auto t1 = std::chrono::steady_clock::now();
    Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
    llt.analyzePattern(K);
    const auto t2 = std::chrono::steady_clock::now();
    const double lnz = llt.cholmod().lnz, fl = llt.cholmod().fl;
    fmt::print("assembly {:.2f} s; CHOLMOD analysis {:.2f} s: factor {:.4g} entries ({:.3f} GB), {:.4g} flop\n",
               std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(), lnz,
               lnz * 8 / 1e9, fl);
  }
  return 0;
}
