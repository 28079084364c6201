#pragma once
// What rank 0 reads of a run with local particles (parallel/decomposition.hpp), without a
// gathered copy of the whole system: O(N / ranks) on rank 0 plus what is small by nature.
//  - the history rows' and the summary's damage statistics and body velocities are exact
//    grid sums and maxima over each rank's owned particles (driver/summary.hpp);
//  - crack tracking and the summary's crack figures read only the cracked particles
//    (damage at or above the tracker's threshold: damage/crack_metrics.hpp looks at no
//    other), gathered by gather_cracked;
//  - the figures that read every particle in the serial order (state_crc32, the models'
//    dissipation parts) stream the state through rank 0 a slice of global ids at a time
//    (stream_on_lead), at the end of the run only.
// Defined in parallel/decomposition.cpp, the one unit the MPI program compiles with MPI.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace horizon {

struct System;
struct Particles;
struct Decomposition;

// The owned particles of every rank with damage >= threshold, on rank 0 in ascending global
// id, into `out`: their global id, reference position X and damage (every other field
// zero); other ranks' `out` is emptied. Without local particles on several ranks, this
// rank's particles of `s` with damage >= threshold (every particle's state is on every
// rank then). Collective.
void gather_cracked(const System& s, const Decomposition* d, double threshold, Particles& out);

// Hands every particle of the whole system to `take(g, values)` on rank 0 in ascending
// global id g, with the `width` values its owner's `pack(i, out)` appended for it (i a
// local index). On several ranks the owners send a slice of ceil(N / ranks) global ids at
// a time, so rank 0 holds one slice (with or without local particles: without, the
// owners' values are the current ones of a model's fields); on one rank and serially this
// process packs and takes every particle. Collective.
void stream_on_lead(const System& s, const Decomposition* d, int width,
                    const std::function<void(uint32_t, std::vector<double>&)>& pack,
                    const std::function<void(std::size_t, const double*)>& take);

}  // namespace horizon
