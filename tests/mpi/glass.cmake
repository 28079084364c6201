# The glass-branching demo (examples/glass_branching.yaml, Ha and Bobaru 2010) reduced to
# cost seconds: spacing 1 mm instead of 0.25 mm (100 x 40 particles), horizon 3 spacings,
# the loaded edge rows one spacing deep, the same 43 us and 2 MPa. It must crack from the
# notch; the serial program and the MPI program on 1, 2, 3 and 4 ranks give the same bytes
# (tests/mpi/same_bytes.cmake: history.csv, state_crc32, the summary's figures).
# cmake -DHORIZON=... -DSERIAL=... -DMPIEXEC=... -DSOURCE=... -DWORK=... -P glass.cmake
include(${CMAKE_CURRENT_LIST_DIR}/same_bytes.cmake)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(READ ${SOURCE}/examples/glass_branching.yaml text)
foreach(edit "spacing: 2.5e-4|spacing: 1.0e-3" "horizon: 1.0e-3|horizon: 3.0e-3"
             "min: [-0.05, 0.01975]|min: [-0.05, 0.019]" "max: [0.05, -0.01975]|max: [0.05, -0.019]"
             "frames: 43|frames: 4")
  string(REPLACE "|" ";" pair "${edit}")
  list(GET pair 0 from)
  list(GET pair 1 to)
  string(FIND "${text}" "${from}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "examples/glass_branching.yaml has no '${from}': update tests/mpi/glass.cmake")
  endif()
  string(REPLACE "${from}" "${to}" text "${text}")
endforeach()
file(WRITE ${WORK}/glass.yaml "${text}")
same_bytes(glass ${WORK}/glass.yaml 1x1 2x1 3x1 4x1)
string(JSON broken GET "${glass_summary}" damage broken_bonds)
string(JSON particles GET "${glass_summary}" particles)
if(broken LESS 100)
  message(FATAL_ERROR "the reduced glass plate must crack: ${broken} broken bonds")
endif()
message(STATUS "glass branching, ${particles} particles: ${broken} broken bonds, identical on 1-4 ranks")
file(REMOVE_RECURSE ${WORK})
