# The same bytes at any rank count (tests/mpi/same_bytes.cmake: history.csv, state_crc32
# and the summary's energy, damage and loads against the serial program and between the
# MPI runs):
#  - tests/mpi/impact.yaml (PMB, critical stretch with alpha, contact, an indenter) on 1,
#    2, 3 and 4 ranks and 2 ranks x 2 threads; one VTU piece per rank and a .pvtu per
#    frame; the ghosts chosen again during the run;
#  - the same deck with every model on the general force pass whose rows are local
#    (ModelTraits::rows_local: each rank computes its particles' neighbours' rows and
#    keeps their history itself) on 2 and 3 ranks, each yielding or relaxing and
#    breaking bonds; and its 2-rank checkpoint of step 250 restarted on 3 ranks, equal
#    to the uninterrupted run (each model's per-particle, per-bond and per-material
#    records gathered from their owners);
#  - a clear error for a deck the decomposition does not split (finite-element regions
#    with short-range contact).
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P ranks.cmake
include(${CMAKE_CURRENT_LIST_DIR}/same_bytes.cmake)
set(deck ${SOURCE}/tests/mpi/impact.yaml)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

same_bytes(impact ${deck} 1x1 2x1 3x1 4x1 2x2)
foreach(ranks 2 3 4)
  set(out ${WORK}/impact_${ranks}x1)
  file(READ ${out}/summary.json summary)
  string(JSON rebuilds GET "${summary}" halo 0 ghost_rebuilds)
  if(rebuilds LESS 2)
    message(FATAL_ERROR "${ranks} ranks: the ghosts were never chosen again (${rebuilds}); the test must cover it")
  endif()
  math(EXPR last "${ranks} - 1")
  foreach(f 00000 00004)
    if(NOT EXISTS ${out}/frames/frame_${f}.pvtu OR NOT EXISTS ${out}/frames/frame_${f}_p${last}.vtu)
      message(FATAL_ERROR "${ranks} ranks: no frames/frame_${f}.pvtu or its piece frame_${f}_p${last}.vtu")
    endif()
  endforeach()
endforeach()
string(JSON broken GET "${impact_summary}" damage broken_fraction)
if(broken LESS 0.05)
  message(FATAL_ERROR "the deck must crack: broken bond fraction ${broken}")
endif()

# Each model on the general force pass: the impact deck with its material, a critical
# stretch of 0.002 (bonds break; no compression factor) and a checkpoint at step 250.
file(READ ${deck} impact)
string(REPLACE "    micromodulus: 2.1e21\n" "" impact "${impact}")
string(REPLACE "critical_stretch: 0.0005, alpha: 0.25, breaks: after_force" "critical_stretch: 0.002" impact "${impact}")
string(REPLACE "damage_measure: volume}" "damage_measure: volume, checkpoint: {every: 250}}" impact "${impact}")
set(elastic "\n    youngs_modulus: 30.0e9\n    poissons_ratio: 0.25")
set(models
    "elastic_plastic${elastic}\n    yield_stress: 20.0e6"
    "viscoelastic${elastic}\n    lambda_1: 0.5\n    tau_1: 1.0e-6"
    "microplastic\n    youngs_modulus: 30.0e9\n    yield_stretch: 0.0008"
    "correspondence${elastic}\n    stress_law: j2\n    yield_stress: 20.0e6")
foreach(model IN LISTS models)
  string(REGEX MATCH "^[a-z_]+" name "${model}")
  string(REPLACE "model: pmb" "model: ${model}" text "${impact}")
  file(WRITE ${WORK}/${name}.yaml "${text}")
  same_bytes(${name} ${WORK}/${name}.yaml 2x1 3x1)
  string(JSON dissipated GET "${${name}_summary}" energy dissipated)
  string(JSON broken GET "${${name}_summary}" damage broken_fraction)
  if(dissipated LESS_EQUAL 0 OR broken LESS_EQUAL 0)
    message(FATAL_ERROR "${name}: the deck must dissipate and break bonds: dissipated ${dissipated}, broken ${broken}")
  endif()
  # The 2-rank run's checkpoint (step 250 of 400) restarted on 3 ranks.
  set(out ${WORK}/${name}_restart)
  file(COPY ${WORK}/${name}_2x1/checkpoint.hzc DESTINATION ${out})
  execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 3 ${HORIZON} run ${WORK}/${name}.yaml -q -o ${out} --threads 1
                          --restart ${out}/checkpoint.hzc
                  RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name}: restart on 3 ranks: exit ${rc}\n${log}")
  endif()
  foreach(f history.csv)
    file(READ ${WORK}/${name}_2x1/${f} expected)
    file(READ ${out}/${f} found)
    if(NOT found STREQUAL expected)
      message(FATAL_ERROR "${name}: the 2-rank checkpoint restarted on 3 ranks: ${f} differs from the uninterrupted run")
    endif()
  endforeach()
  file(READ ${out}/summary.json summary)
  string(JSON crc GET "${summary}" state_crc32)
  string(JSON expected GET "${${name}_summary}" state_crc32)
  if(NOT crc EQUAL expected)
    message(FATAL_ERROR "${name}: the 2-rank checkpoint restarted on 3 ranks: state_crc32 ${crc}, uninterrupted ${expected}")
  endif()
  message(STATUS "${name}: dissipated ${dissipated} J, broken fraction ${broken}; 2 -> 3 ranks restart identical")
endforeach()

# A deck the decomposition does not split (finite elements with short-range contact: the
# impact deck with a block of hex8 elements beside its cylinder; FE regions without
# contact split: split_models.cmake): a clear error on 2 ranks that says why.
file(READ ${deck} text)
string(REPLACE "    micromodulus: 2.1e21" "    youngs_modulus: 30.0e9" text "${text}")
string(REPLACE "\ncontact:" "
  - {name: block, material: target, discretization: fe, shape: {box: {min: [0.007, -0.005, -0.002], max: [0.010, -0.002, 0.002]}}}
contact:" text "${text}")
file(WRITE ${WORK}/fe.yaml "${text}")
execute_process(COMMAND ${MPIEXEC} --oversubscribe -n 2 ${HORIZON} run ${WORK}/fe.yaml -q -o ${WORK}/fe
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(rc EQUAL 0 OR NOT log MATCHES "cannot run on 2 MPI ranks yet: finite-element regions are not split over ranks")
  message(FATAL_ERROR "a deck with a finite-element body on 2 ranks: exit ${rc}, expected a clear error:\n${log}")
endif()
file(REMOVE_RECURSE ${WORK})
