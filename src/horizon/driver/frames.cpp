// Frames of a run: the particles' fields as a Frame, and its files (one .vtu, or a piece
// a rank and the .pvtu index), for the explicit, implicit and heat drivers.
#include <fmt/format.h>

#include <filesystem>

#include "horizon/driver/run.hpp"
#include "horizon/material/model.hpp"
#include "horizon/output/pvd.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/parallel/decomposition.hpp"

namespace horizon {

namespace fs = std::filesystem;

Frame make_frame(const System& s, double time, int64_t step) {
  const auto& P = s.particles;
  Frame f;
  f.time = time;
  f.step = step;
  f.dimension = s.dimension;
  f.points = P.X;
  auto vec = [&](const std::string& name, const std::vector<Vec3>& v) {
    FrameField ff{name, 3, {}};
    ff.data.reserve(3 * v.size());
    for (const auto& x : v) ff.data.insert(ff.data.end(), {x.x, x.y, x.z});
    f.fields.push_back(std::move(ff));
  };
  auto scal = [&](const std::string& name, auto get) {
    FrameField ff{name, 1, {}};
    ff.data.resize(P.size());
    for (std::size_t i = 0; i < P.size(); ++i) ff.data[i] = get(i);
    f.fields.push_back(std::move(ff));
  };
  vec("displacement", P.u);
  vec("velocity", P.v);
  vec("force_density", P.f);
  scal("damage", [&](std::size_t i) { return P.damage[i]; });
  scal("energy_density", [&](std::size_t i) { return P.energy[i]; });
  scal("block", [&](std::size_t i) { return static_cast<double>(P.block[i]); });
  scal("volume", [&](std::size_t i) { return P.volume[i]; });
  if (s.heat.active()) {
    scal("temperature", [&](std::size_t i) { return s.heat.T[i]; });
    vec("heat_flux", s.heat.flux);
  }
  // The models' own fields (material/model.hpp), once per name: a run with two materials
  // of one model writes its fields once.
  std::vector<ModelField> extra;
  for (const auto& m : s.models) m->fields(s, extra);
  for (auto& mf : extra) {
    bool seen = false;
    for (const auto& ff : f.fields) seen = seen || ff.name == mf.name;
    if (seen || mf.values.size() != P.size()) continue;
    f.fields.push_back(FrameField{mf.name, 1, std::move(mf.values)});
  }
  return f;
}

void write_frame_files(const std::string& directory, const std::string& base, const Frame& f, double time,
                       PvdIndex& pvd, const Decomposition* dd) {
  const fs::path dir = directory;
  if (!dd) {
    const std::string name = "frames/" + base + ".vtu";
    write_vtu((dir / name).string(), f);
    pvd.add(time, name);
    pvd.write();
    return;
  }
  // One piece per rank, its own particles; the index once all pieces are complete.
  write_vtu((dir / "frames" / fmt::format("{}_p{}.vtu", base, dd->rank)).string(), frame_subset(f, dd->owned));
  any_rank(*dd, false);  // a barrier
  if (dd->rank != 0) return;
  std::vector<std::string> pieces;
  for (int r = 0; r < dd->size; ++r) pieces.push_back(fmt::format("{}_p{}.vtu", base, r));
  const std::string name = "frames/" + base + ".pvtu";
  write_pvtu((dir / name).string(), f, pieces);
  pvd.add(time, name);
  pvd.write();
}

}  // namespace horizon
