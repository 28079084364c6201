// The static stage of a staged run (Config::static_stage; docs/input.md "Solver stages"):
// a static solve on the explicit run's own system and writers, then the explicit stage
// from its last equilibrium. Peridigm's QuasiStatic solver followed by its Verlet solver
// (docs/peridigm.md): Compression_QS_Explicit_3x2x2's gold pins what the switch does:
//   - the static stage's outputs are its load steps 1..N at t_k = T1 k / N (or the listed
//     load_times), each with the
//     quasi-static velocity (u_k - u_{k-1}) / (t_k - t_{k-1});
//   - the explicit stage starts at T1 with that velocity at every particle (the gold's
//     middle column keeps VelocityX -1000 = -0.05 / 5e-5 and moves by -1000 dt a step),
//     and its start state is written again at T1 (the gold holds t = 5e-5 twice, the
//     same values);
//   - prescribed displacements keep following their function of t (the loaded face moves
//     on at -2000 m/s, u = -0.1 t / 5e-5);
//   - the output steps count on: the start state is step N + 1 and the n-th explicit
//     step N + 1 + n (the MultiFreqOutput gold's list "every 100 from step 21" holds
//     t = T1 + 79 dt, ..., T1 + 479 dt).
#include "horizon/driver/explicit_state.hpp"
#include "horizon/solver/static_driver.hpp"

namespace horizon {

void ExplicitRun::State::run_static_stage() {
  const SolverConfig& sc = *config.static_stage;
  auto& P = s.particles;
  StaticSolver statics(s, *loads, sc);
  statics.initialize();
  if (!options.quiet)
    fmt::print(stderr, "stage 1         static, {} load steps to t = {:.4e} s\n", sc.load_steps, config.solver.start_time);
  // The stage's frames: output.frames of them over its load steps (as a static run's);
  // the explicit stage writes its own output.frames after.
  const int frames_here = std::max(1, config.output.frames);
  int next = 1;
  int64_t last_whole = 0;  // the last whole load step written
  double h = 0;            // the last increment's time
  std::string switched;    // on_failure: explicit: why the static stage ended early
  while (!statics.done()) {
    const double before = statics.time();
    const std::vector<Vec3> u_before = P.u;
    if (!statics.advance()) {
      // The state is the last converged one (the velocity its increment's, or the initial
      // one); on_failure: explicit goes on from it explicitly (Peridigm's Switch to Verlet).
      if (sc.switch_on_failure) {
        switched = statics.failure();
        break;
      }
      status = "not converged";
      exit_code = 4;
      message = "static stage: " + statics.failure();
      stopped = true;
      break;
    }
    h = statics.time() - before;
    for (std::size_t i = 0; i < P.size(); ++i) P.v[i] = (P.u[i] - u_before[i]) / h;
    // Outputs at whole load steps (a cut increment's parts end between them).
    const int64_t k = statics.load_step();
    if (k <= last_whole) continue;
    last_whole = k;
    const double t = statics.time();
    record_history(t, k, h, statics.ledger());
    if (statics.lambda() * frames_here >= next - 1e-9) {
      write_frame(t, k);
      while (statics.lambda() * frames_here >= next - 1e-9) ++next;
    }
    if (exodus_files && exodus_files->due(k)) exodus_files->write(s, dd.get(), t, k);
  }
  stage_summary = {{"type", "static"},
                   {"load_steps", sc.load_steps},
                   {"time", statics.time()},
                   {"load_factor", statics.lambda()},
                   {"iterations", statics.total_iterations()},
                   {"linear_iterations", statics.total_linear_iterations()},
                   {"step_cuts", statics.total_cuts()},
                   {"external_work", statics.ledger().external_work},
                   {"strain_energy", statics.ledger().strain}};
  if (stopped) return;
  // The explicit stage: from T1, prescribed velocities the displacements' rate over the
  // last increment (the same quasi-static velocity), the others as set above. After a
  // failed increment (on_failure: explicit): from the last converged state, at its time
  // and after its whole load steps, to the explicit stage's end_time.
  double t0 = config.solver.start_time;
  step_offset = sc.load_steps + 1;
  if (!switched.empty()) {
    t0 = statics.time();
    step_offset = last_whole + 1;
    stage_summary["switched_to_explicit"] = {{"time", t0}, {"after_load_steps", last_whole}, {"failure", switched}};
    if (!options.quiet)
      fmt::print(stderr, "stage 1         switched to explicit at t = {:.4e} s after {} load step(s): {}\n", t0,
                 last_whole, switched);
  }
  solver->initialize(t0, h);
  // The steps left to end_time from the switch, as the check counts them from T1.
  total = static_cast<int64_t>(std::ceil((config.solver.end_time - t0) / solver->dt() - 1e-9));
  if (exodus_files) exodus_files->set_explicit_from(step_offset);
  record_history();
  write_frame();
  if (exodus_files) {
    exodus_files->set_verlet(loads.get(), 0);  // the start state: no half kick
    if (exodus_files->due(step_offset)) exodus_files->write(s, dd.get(), solver->time(), step_offset);
  }
  if (!options.quiet)
    fmt::print(stderr, "stage 2         explicit from t = {:.4e} s ({} Newton iterations in the static stage)\n",
               solver->time(), statics.total_iterations());
}

}  // namespace horizon
