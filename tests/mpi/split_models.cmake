# The decks that owned their own path through a run and were refused on more than one
# rank, now split (docs/design.md "Running on several ranks"), each with the same bytes
# at any rank count (tests/mpi/same_bytes.cmake: history.csv, state_crc32 and the
# summary's energy, damage and loads, between the MPI runs on 1, 2, 3 ranks and 2 ranks
# x 2 threads; state_crc32 equal to the serial program's):
#  - Tupek's nonlinear solid (tests/mpi/kalthoff.yaml: its own force pass, the energy
#    failure law, the adaptive time step as the minimum over ranks, mass damping with
#    its damped energy summed on the grid, the crack faces' contact). It must break
#    bonds, damp energy and change its step; its 2-rank checkpoint restarted on 3 ranks
#    gives the uninterrupted run's history.csv and state_crc32 (theta, the bond strains
#    and the nonlocal damage gathered from their owners).
#  - finite-element regions (tests/mpi/fe_plate.yaml: a cracked peridynamic core in J2-plastic
#    hex8 elements of size 2, fe/fe_region.hpp FeRegion::split: each rank evaluates the
#    elements of its FE-owned nodes, interpolates the band's particles it reads, sums the
#    coupling work on the grid; the element history is checkpointed from one owner per
#    element). It must break bonds and couple through shared nodes; serial = 2, 3 ranks
#    and 2 x 2 threads (1 and 4 ranks too, by hand: docs/verification.md); its 2-rank
#    checkpoint restarted on 3 ranks gives the uninterrupted run. The same deck with
#    short-range contact is refused on 2 ranks.
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P split_models.cmake
include(${CMAKE_CURRENT_LIST_DIR}/same_bytes.cmake)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

# Tupek's nonlinear solid, with a checkpoint every 100 steps.
file(READ ${SOURCE}/tests/mpi/kalthoff.yaml text)
string(REPLACE "history_every: 20}" "history_every: 20, checkpoint: {every: 100}}" text "${text}")
file(WRITE ${WORK}/kalthoff.yaml "${text}")
same_bytes(kalthoff ${WORK}/kalthoff.yaml 1x1 2x1 3x1 2x2)
string(JSON broken GET "${kalthoff_summary}" damage broken_bonds)
string(JSON damped GET "${kalthoff_summary}" energy damped)
string(JSON dt_min GET "${kalthoff_summary}" time_step_range 0)
string(JSON dt_max GET "${kalthoff_summary}" time_step_range 1)
if(broken LESS 100 OR NOT damped GREATER 0 OR NOT dt_max GREATER dt_min)
  message(FATAL_ERROR "the nonlinear solid deck must break bonds (${broken}), damp energy (${damped} J) and change "
                      "its step (${dt_min} to ${dt_max} s)")
endif()
message(STATUS "kalthoff: ${broken} broken bonds, damped ${damped} J, step ${dt_min} to ${dt_max} s")
restart_on_three(kalthoff ${WORK}/kalthoff.yaml)

# Finite-element regions (plastic elements, a crack in the peridynamic core).
same_bytes(fe_plate ${SOURCE}/tests/mpi/fe_plate.yaml 2x1 3x1 2x2)
string(JSON broken GET "${fe_plate_summary}" damage broken_bonds)
string(JSON shared GET "${fe_plate_summary}" fe shared_nodes)
string(JSON elements GET "${fe_plate_summary}" fe elements)
if(broken LESS 100 OR shared LESS 1)
  message(FATAL_ERROR "the finite-element deck must break bonds (${broken}) and share nodes with the core (${shared})")
endif()
message(STATUS "fe_plate: ${elements} elements, ${shared} shared nodes, ${broken} broken bonds")
restart_on_three(fe_plate ${SOURCE}/tests/mpi/fe_plate.yaml)
file(READ ${SOURCE}/tests/mpi/fe_plate.yaml text)
file(WRITE ${WORK}/fe_contact.yaml "${text}contact: {short_range: {max_distance: 0.9}}\n")
execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 2 ${HORIZON} run ${WORK}/fe_contact.yaml -q -o ${WORK}/fe_contact
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(rc EQUAL 0 OR NOT log MATCHES "finite-element regions are not split over ranks with short-range contact")
  message(FATAL_ERROR "fe_contact: a finite-element deck with short-range contact must be refused on 2 ranks (exit ${rc}):\n${log}")
endif()
message(STATUS "fe_contact: refused on 2 ranks")

file(REMOVE_RECURSE ${WORK})
