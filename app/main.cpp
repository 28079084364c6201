// The `horizon` command line: run, check, export-truss, render, plot, models, --version. It only chains library
// calls; every stage lives in src/horizon.
#if defined(HORIZON_MPI)
#include <mpi.h>
#endif
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <csignal>
#include <exception>

#include "horizon/core/error.hpp"
#include "horizon/core/version.hpp"
#include "horizon/deck/deck.hpp"
#include "horizon/driver/run.hpp"
#include "horizon/output/atomic_file.hpp"
#include "horizon/material/model.hpp"
#include "horizon/output/plot.hpp"
#include "horizon/output/render.hpp"
#include "horizon/output/truss.hpp"
#include "horizon/output/resolve_frame.hpp"
#include "horizon/output/vtu.hpp"
#include "horizon/parallel/decomposition.hpp"

namespace {
int horizon_main(int argc, char** argv) {
  using namespace horizon;
  CLI::App app{"Horizon: a peridynamics engine"};
  app.set_version_flag("--version", std::string("horizon ") + version_string);
  app.require_subcommand(1);

  RunOptions run_opts;
  std::string deck_path;
  std::string out_dir;
  auto* run = app.add_subcommand("run", "run a deck and write frames, history.csv and summary.json");
  run->add_option("deck", deck_path, "the deck (YAML)")->required();
  run->add_option("-o,--output", out_dir, "output directory (overrides output.directory)");
  run->add_option("--coarsen", run_opts.coarsen, "multiply spacing and horizon by this factor (quick looks, smoke tests)")
      ->check(CLI::PositiveNumber);
  double end_time = 0;
  run->add_option("--end-time", end_time, "override solver.end_time [s]")->check(CLI::PositiveNumber);
  run->add_option("--threads", run_opts.threads, "OpenMP threads (default: all cores)")->check(CLI::NonNegativeNumber);
  run->add_flag("-q,--quiet", run_opts.quiet, "no progress line");
  std::string backend;
  run->add_option("--backend", backend,
                  "what takes the explicit steps: cpu, flat (the portable kernels on the host) or cuda (overrides "
                  "solver.backend)")
      ->check(CLI::IsMember({"cpu", "flat", "cuda"}));
  std::string restart_path;
  run->add_option("--restart", restart_path,
                  "continue from a checkpoint (output.checkpoint) of this deck, in its output directory");
  run->add_option("--max-memory", run_opts.max_memory_gib,
                  "refuse decks estimated to need more than this [GiB] (default: the machine's memory)")
      ->check(CLI::PositiveNumber);

  auto* check = app.add_subcommand("check", "validate a deck; print particles, bonds, memory and time step");
  check->add_option("deck", deck_path, "the deck (YAML)")->required();
  check->add_option("--coarsen", run_opts.coarsen, "as for run")->check(CLI::PositiveNumber);
  check->add_option("--max-memory", run_opts.max_memory_gib, "as for run")->check(CLI::PositiveNumber);
  int check_ranks = 0;
  check->add_option("--ranks", check_ranks, "also the bonds and memory of one of N MPI ranks (horizon-mpi)")
      ->check(CLI::Range(1, 1 << 20));

  std::string truss_path = "trusses.txt";
  auto* export_truss = app.add_subcommand(
      "export-truss", "write the bond network of a bond-based deck as truss elements with lumped masses (seed 002 sec. 6)");
  export_truss->add_option("deck", deck_path, "the deck (YAML)")->required();
  export_truss->add_option("-o,--output", truss_path, "the truss file (default trusses.txt)");
  export_truss->add_option("--coarsen", run_opts.coarsen, "as for run")->check(CLI::PositiveNumber);

  std::string frame_path, png_path, field = "damage";
  RenderOptions render_opts;
  auto* render = app.add_subcommand("render", "draw a frame (or the last frame of a run directory) to PNG, SVG or PDF");
  render->add_option("frame", frame_path, "a .vtu frame, a .pvd index, or a run's output directory")->required();
  render->add_option("--field", render_opts.field,
                     "field to colour by (damage, displacement = its magnitude, displacement_x, any field of the frame)");
  render->add_option("-o,--output", png_path, "picture file, .png, .svg or .pdf (default: <field>.png beside the frame)");
  render->add_option("--width", render_opts.width, "picture width in pixels")->check(CLI::Range(64, 8192));
  render->add_option("--scale", render_opts.displacement_scale, "displacement magnification");
  render->add_option("--slice", render_opts.slice, "3-D bodies: the particles of one plane, e.g. z=0.001");
  render->add_option("--view", render_opts.view, "3-D bodies without --slice: the projection's direction (x, y, z)")
      ->check(CLI::IsMember({'x', 'y', 'z'}));
  double vmin = NAN, vmax = NAN;
  render->add_option("--vmin", vmin, "bottom of the colour range (default: the field's minimum)");
  render->add_option("--vmax", vmax, "top of the colour range (default: the field's maximum)");
  render->add_option("--title", render_opts.title, "text before the time");

  PlotRequest plot_req;
  auto* plot = app.add_subcommand("plot", "plot columns of runs' history.csv to PNG, SVG or PDF and print the peaks");
  plot->add_option("history", plot_req.histories, "history.csv files or run output directories (a sweep: one curve each)")
      ->required();
  plot->add_option("--x", plot_req.x_column, "column for the horizontal axis (e.g. load:displacement_uy)")->required();
  plot->add_option("--y", plot_req.y_columns, "column for the vertical axis (e.g. load:displacement_fy); repeat for more curves")
      ->required();
  plot->add_option("--x-scale", plot_req.x_scale, "multiply x by this (e.g. -1 for the sign)");
  plot->add_option("--y-scale", plot_req.y_scale, "multiply y by this (e.g. -1 for the sign)");
  plot->add_option("--x-label", plot_req.x_label, "horizontal axis title (default: the quantity and its unit)");
  plot->add_option("--y-label", plot_req.y_label, "vertical axis title (default: the quantity and its unit)");
  std::string plot_title;
  auto* plot_title_opt = plot->add_option("--title", plot_title, "title above the plot (default: the run's directory name)");
  plot->add_option("--width", plot_req.width, "width in pixels (points for SVG, PDF)")->check(CLI::Range(200, 8192));
  plot->add_option("--height", plot_req.height, "height in pixels (points for SVG, PDF)")->check(CLI::Range(150, 8192));
  plot->add_option("-o,--output", plot_req.output, "picture file, .png, .svg or .pdf (default: <y>.png beside the history)");

  auto* models = app.add_subcommand("models", "list the material models with their deck parameters");

  std::string convert_out;
  auto* convert = app.add_subcommand("convert", "translate a Peridigm deck (YAML) into the equivalent native deck");
  convert->add_option("deck", deck_path, "the Peridigm deck (top-level key Peridigm)")->required();
  convert->add_option("-o,--output", convert_out, "the native deck to write (default: standard output)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  // A file-size limit (ulimit -f) makes write(2) fail with EFBIG instead of killing the
  // process, so that it ends as an output error with its message (exit status 5).
  std::signal(SIGXFSZ, SIG_IGN);
  // Exit statuses (docs/reliability.md): 0 completed, 1 bad input, 2 non-finite state,
  // 3 internal error, 4 not converged, 5 output could not be written, 130/143 SIGINT/SIGTERM.
  try {
    if (*run) {
      if (!out_dir.empty()) run_opts.output_dir = out_dir;
      if (end_time > 0) run_opts.end_time = end_time;
      if (!restart_path.empty()) run_opts.restart = restart_path;
      if (!backend.empty()) run_opts.backend = backend;
      Config config = load_deck(deck_path);
      for (const auto& w : config.warnings) fmt::print(stderr, "{}\n", w);
      return run_deck(std::move(config), run_opts);
    }
    if (*check) {
      Config config = load_deck(deck_path);
      for (const auto& w : config.warnings) fmt::print(stderr, "{}\n", w);
      apply_run_options(config, run_opts);
      const PreparedRun u = prepare_run(config);
      fmt::print("{}", format_check(config, u.check));
      if (check_ranks > 1) {
        // Each rank of horizon-mpi holds its own bond rows and, where the deck allows it,
        // only the particles they read (parallel/decomposition.hpp, local rows and local
        // particles), or the whole system where those do not apply.
        if (local_rows_allowed(config)) {
          const bool local = local_particles_allowed(config);
          const RankShare r = largest_rank_share(u.system, check_ranks, local);
          auto pct = [](uint64_t part, uint64_t whole) {
            return whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
          };
          fmt::print("on {} ranks     at most {} particles ({:.1f} %{}) and {} bonds ({:.1f} %) on a rank, memory {:.1f} "
                     "MiB a rank (estimate)\n",
                     check_ranks, r.particles, pct(r.particles, u.check.particles),
                     local ? "" : ": every particle on every rank", r.bonds, pct(r.bonds, u.check.bonds),
                     static_cast<double>(r.bytes) / (1 << 20));
        } else {
          fmt::print("on {} ranks     every rank holds the whole system (this deck is not split by bond rows)\n",
                     check_ranks);
        }
      }
      fmt::print("deck is valid\n");
      return 0;
    }
    if (*export_truss) {
      Config config = load_deck(deck_path);
      for (const auto& w : config.warnings) fmt::print(stderr, "{}\n", w);
      apply_run_options(config, run_opts);
      const System s = build_system(config);
      const TrussNetwork net = truss_network(s);
      write_truss_file(truss_path, s, net);
      fmt::print("wrote {}: {} nodes, {} trusses\n", truss_path, net.mass.size(), net.trusses.size());
      return 0;
    }
    if (*convert) {
      const std::string text = convert_peridigm_deck(deck_path);
      if (convert_out.empty()) {
        fmt::print("{}", text);
      } else {
        write_file_atomic(convert_out, text);
        fmt::print(stderr, "wrote {}\n", convert_out);
      }
      return 0;
    }
    if (*models) {
      fmt::print("{}", describe_models());
      return 0;
    }
    if (*plot) {
      if (*plot_title_opt) plot_req.title = plot_title;
      const PlotCommandResult r = plot_history(plot_req);
      for (std::size_t k = 0; k < r.peaks.size(); ++k)
        fmt::print("peak {} = {:.6g} at {} = {:.6g} (row {})\n", r.labels[k], r.peaks[k].y, plot_req.x_column,
                   r.peaks[k].x, r.peaks[k].index);
      fmt::print("wrote {}\n", r.path);
      return 0;
    }
    if (*render) {
      const std::string frame = resolve_frame(frame_path);
      if (png_path.empty()) png_path = (std::filesystem::path(frame).parent_path() / (render_opts.field + ".png")).string();
      if (std::isfinite(vmin)) render_opts.vmin = vmin;
      if (std::isfinite(vmax)) render_opts.vmax = vmax;
      const RenderResult r = render_png(read_vtu(frame), render_opts, png_path);
      fmt::print("wrote {} ({} particles; {}: {:.6g} to {:.6g})\n", png_path, r.drawn, render_opts.field, r.lo, r.hi);
      return 0;
    }
  } catch (const OutputError& e) {
    fmt::print(stderr, "horizon: output error: {}\n", e.what());
    return 5;
  } catch (const Error& e) {
    fmt::print(stderr, "horizon: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "horizon: internal error: {}\n", e.what());
    return 3;
  }
  return 0;
}
}  // namespace

// An MPI build (HORIZON_MPI) runs under mpirun, and alone as one rank.
int main(int argc, char** argv) {
#if defined(HORIZON_MPI)
  MPI_Init(&argc, &argv);
  const int rc = horizon_main(argc, argv);
  MPI_Finalize();
  return rc;
#else
  return horizon_main(argc, argv);
#endif
}
