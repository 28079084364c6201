# The CUDA backend (src/horizon/cuda/, issue 30; docs/design.md, "Backends and portable
# kernels"), its GPU test (label gpu) and benchmark. Included by CMakeLists.txt with
# -DHORIZON_CUDA=ON, after the rest of the build, or alone with -DHORIZON_GPU_ONLY=ON (the
# device machine: nvcc, CMake and ninja, none of the Debian libraries the rest needs).
# The CUDA sources include only the portable kernel headers (src/horizon/kernels/, core/).
#
# Compiled with nvcc 13.0 (sm_90) on the development machine, which has no GPU: never run yet.
if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
  set(CMAKE_CUDA_ARCHITECTURES 90)  # Hopper (H100, H200): sm_90 machine code
endif()
enable_language(CUDA)
find_package(CUDAToolkit REQUIRED)
set(CMAKE_CUDA_STANDARD 17)
set(CMAKE_CUDA_STANDARD_REQUIRED ON)

add_library(horizon_cuda STATIC ${PROJECT_SOURCE_DIR}/src/horizon/cuda/cuda_backend.cu
                                ${PROJECT_SOURCE_DIR}/src/horizon/cuda/cuda_ordinary.cu)
# Not the directory's host options (-Wall ...: nvcc takes them through -Xcompiler).
set_property(TARGET horizon_cuda PROPERTY COMPILE_OPTIONS "")
# No fused multiply-add contraction: the device computes each row with the host's
# operations, in the host's order (kernels/flat_system.hpp); sqrt and division are IEEE
# (nvcc's defaults -prec-sqrt=true, -prec-div=true).
target_compile_options(horizon_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--fmad=false -Xcompiler=-Wall,-Wextra>)
target_include_directories(horizon_cuda PUBLIC ${PROJECT_SOURCE_DIR}/src)
target_link_libraries(horizon_cuda PUBLIC CUDA::cudart)

# The portable law kernels that no device pass calls yet (kernels/laws.hpp, eigen3.hpp:
# the correspondence model's neo-Hookean and J2 rows), compiled for the device in every
# GPU build so that device_check.sh checks them in its one call (nothing runs them);
# kernels_compile_models.cu: those of microplastic, PALS, the linearised LPS and bond_pair.
add_library(horizon_kernels_compile OBJECT ${PROJECT_SOURCE_DIR}/tests/gpu/kernels_compile.cu
                                          ${PROJECT_SOURCE_DIR}/tests/gpu/kernels_compile_models.cu)
set_property(TARGET horizon_kernels_compile PROPERTY COMPILE_OPTIONS "")
target_compile_options(horizon_kernels_compile PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:--fmad=false -Xcompiler=-Wall,-Wextra>)
target_include_directories(horizon_kernels_compile PRIVATE ${PROJECT_SOURCE_DIR}/src)

add_executable(test_cuda_flat ${PROJECT_SOURCE_DIR}/tests/gpu/test_cuda_flat.cpp)
target_link_libraries(test_cuda_flat PRIVATE horizon_cuda)
add_executable(bench_cuda ${PROJECT_SOURCE_DIR}/bench/gpu/bench_cuda.cpp)
target_link_libraries(bench_cuda PRIVATE horizon_cuda)

enable_testing()
# Exit status 77: no CUDA device here (skipped, with the test's message).
add_test(NAME gpu_cuda_flat COMMAND test_cuda_flat)
set_tests_properties(gpu_cuda_flat PROPERTIES LABELS gpu SKIP_RETURN_CODE 77)

# In a whole build (the library is there): the driver's backend cuda (solver.backend,
# driver/backends.cpp) over FlatRun, and the CUDA backend against the CPU backend on a
# deck, through the flat copy of a System (solver/flat_copy.hpp).
if(TARGET horizon_lib)
  set_property(TARGET horizon_cuda PROPERTY POSITION_INDEPENDENT_CODE ON)  # the Python module links the library
  target_link_libraries(horizon_lib PUBLIC horizon_cuda)
  set_source_files_properties(${PROJECT_SOURCE_DIR}/src/horizon/driver/backends.cpp PROPERTIES
                              COMPILE_DEFINITIONS HORIZON_CUDA_BACKEND=1)
  add_executable(test_cuda_system ${PROJECT_SOURCE_DIR}/tests/gpu/test_cuda_system.cpp)
  target_link_libraries(test_cuda_system PRIVATE horizon_lib horizon_cuda)
  add_test(NAME gpu_cuda_system COMMAND test_cuda_system)
  set_tests_properties(gpu_cuda_system PROPERTIES LABELS gpu SKIP_RETURN_CODE 77)
endif()
