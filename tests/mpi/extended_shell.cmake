# More models once refused on more than one rank, now split (docs/design.md "Running on
# several ranks"), each with the same bytes at any rank count (tests/mpi/same_bytes.cmake:
# history.csv, state_crc32 and the summary's energy, damage and loads, between the MPI
# runs on 1, 2, 3 ranks and 2 ranks x 2 threads; state_crc32 equal to the serial
# program's):
#  - Tupek's extended correspondence (tests/mpi/extended.yaml: the general force pass,
#    the neighbours' rows computed here; the ghosts' committed Johnson-Cook damage for the
#    damage-dependent influence, their stabilisation modulus and midpoint strain E sent
#    by their owners between the sweeps; contact; the adaptive step from its spring
#    factors). Particles must fail (failure energy and the acting-set energy of omega_D)
#    and the step must change; its 2-rank checkpoint restarted on 3 ranks is identical;
#    without contact, on 3 ranks with local particles, the serial program's state.
#    Without the capped stabilisation the model takes its pair form of the pass: the
#    same checks (below).
#  - O'Grady's bond-pair shell (tests/mpi/shell.yaml: its own pair pass split by the
#    nodes each rank owns, the support ghosts' forces gathered in the serial order, the
#    supports' reactions added once). Pairs must yield and fail; its 2-rank checkpoint
#    restarted on 3 ranks is identical.
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P extended_shell.cmake
include(${CMAKE_CURRENT_LIST_DIR}/same_bytes.cmake)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# Tupek's extended correspondence, with a checkpoint every 400 steps (the last at 800 of 1,075).
file(READ ${SOURCE}/tests/mpi/extended.yaml text)
string(REPLACE "history_every: 50}" "history_every: 50, checkpoint: {every: 400}}" text "${text}")
file(WRITE ${WORK}/extended.yaml "${text}")
same_bytes(extended ${WORK}/extended.yaml 1x1 2x1 3x1 2x2)
string(JSON failure GET "${extended_summary}" energy dissipated_parts failure_energy)
string(JSON acting GET "${extended_summary}" energy dissipated_parts acting_set_energy)
string(JSON dt_min GET "${extended_summary}" time_step_range 0)
string(JSON dt_max GET "${extended_summary}" time_step_range 1)
if(NOT failure GREATER 0 OR acting EQUAL 0 OR NOT dt_max GREATER dt_min)
  message(FATAL_ERROR "the extended correspondence deck must fail particles (failure energy ${failure} J), drop "
                      "their bonds (acting-set energy ${acting} J) and change its step (${dt_min} to ${dt_max} s)")
endif()
message(STATUS "extended: failure energy ${failure} J, acting-set energy ${acting} J, step ${dt_min} to ${dt_max} s")
restart_on_three(extended ${WORK}/extended.yaml)
# Without contact and checkpoints each rank holds only the particles it reads (local
# particles, local numbering): the same exchange, the serial program's state.
file(READ ${SOURCE}/tests/mpi/extended.yaml text)
string(REPLACE "contact: {short_range: {max_distance: 0.9}}\n" "" text "${text}")
file(WRITE ${WORK}/extended_local.yaml "${text}")
same_bytes(extended_local ${WORK}/extended_local.yaml 3x1)
string(JSON local GET "${extended_local_summary}" particles_local)
if(NOT local)
  message(FATAL_ERROR "the extended correspondence deck without contact must hold local particles on 3 ranks")
endif()

# The same deck without the capped stabilisation takes the extended model's pair form of
# the general pass (extended_correspondence.cpp pair_forces: its own breaking sweep, the
# midpoint's E from the owners, no force state per bond): the same bytes on 1 to 3 ranks
# as serially, its 2-rank checkpoint (the last pass's bond scalars, PK and positions for
# the booking of breaks) restarted on 3 ranks identical, and the local-particle split.
file(READ ${SOURCE}/tests/mpi/extended.yaml text)
string(REPLACE "    stabilization_yield: 3.0\n" "" text "${text}")
string(REPLACE "history_every: 50}" "history_every: 50, checkpoint: {every: 400}}" pair "${text}")
file(WRITE ${WORK}/extended_pair.yaml "${pair}")
same_bytes(extended_pair ${WORK}/extended_pair.yaml 2x1 3x1)
string(JSON failure GET "${extended_pair_summary}" energy dissipated_parts failure_energy)
if(NOT failure GREATER 0)
  message(FATAL_ERROR "the extended pair-form deck must fail particles (failure energy ${failure} J)")
endif()
restart_on_three(extended_pair ${WORK}/extended_pair.yaml)
string(REPLACE "contact: {short_range: {max_distance: 0.9}}\n" "" text "${text}")
file(WRITE ${WORK}/extended_pair_local.yaml "${text}")
same_bytes(extended_pair_local ${WORK}/extended_pair_local.yaml 3x1)

# O'Grady's bond-pair shell, with a checkpoint every 120 steps (the last at 120 of 210).
file(READ ${SOURCE}/tests/mpi/shell.yaml text)
string(REPLACE "history_every: 50}" "history_every: 50, checkpoint: {every: 120}}" text "${text}")
file(WRITE ${WORK}/shell.yaml "${text}")
same_bytes(shell ${WORK}/shell.yaml 1x1 2x1 3x1 2x2)
string(JSON damage GET "${shell_summary}" damage max)
string(JSON dissipated GET "${shell_summary}" energy dissipated)
if(NOT damage GREATER 0 OR NOT dissipated GREATER 0)
  message(FATAL_ERROR "the shell deck must fail pairs (damage ${damage}) and yield (dissipated ${dissipated} J)")
endif()
message(STATUS "shell: largest damage ${damage}, dissipated ${dissipated} J")
restart_on_three(shell ${WORK}/shell.yaml)
file(REMOVE_RECURSE ${WORK})
