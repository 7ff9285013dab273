# Sanitizer and fuzzing builds (deploy/sanitizers.sh, deploy/fuzz.sh). Included by the top-level
# CMakeLists.txt before any target exists, so every target (core, server, daemon, tests) is built
# the same way and lbsolidd started by the service tests is the sanitized one.
#
#   -DLBSOLID_SANITIZE=address,undefined   ASan + UBSan (gcc or clang)
#   -DLBSOLID_SANITIZE=thread              TSan (cannot be combined with address)
#   -DLBSOLID_FUZZ=ON                      clang only: instruments every library for libFuzzer
#                                          (-fsanitize=fuzzer-no-link); tests/fuzz links the
#                                          fuzz targets with -fsanitize=fuzzer. Use it together
#                                          with LBSOLID_SANITIZE=address,undefined.
#
# Either one means -O1 -g -fno-omit-frame-pointer (readable stacks, tolerable speed), every report
# fatal (-fno-sanitize-recover=all: a UBSan report aborts instead of printing and going on), and no
# -march=native (the build must behave the same on any machine that runs it).
set(LBSOLID_SANITIZE "" CACHE STRING
    "Comma-separated -fsanitize= list for the whole build (e.g. address,undefined or thread); empty: none")
option(LBSOLID_FUZZ "Build the libFuzzer targets of tests/fuzz (clang only; -fsanitize=fuzzer-no-link everywhere)" OFF)

if(LBSOLID_SANITIZE MATCHES "thread" AND LBSOLID_SANITIZE MATCHES "address")
  message(FATAL_ERROR "LBSOLID_SANITIZE: thread and address cannot be combined (two builds)")
endif()
if(LBSOLID_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "LBSOLID_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14")
endif()

set(lbsolid_sanitize_list "${LBSOLID_SANITIZE}")
if(LBSOLID_FUZZ)
  if(lbsolid_sanitize_list)
    string(APPEND lbsolid_sanitize_list ",fuzzer-no-link")
  else()
    set(lbsolid_sanitize_list "fuzzer-no-link")
  endif()
endif()

if(lbsolid_sanitize_list)
  message(STATUS "lbsolid: sanitized build (-fsanitize=${lbsolid_sanitize_list}), -O1 -g, no -march=native")
  set(LBSOLID_NATIVE OFF)  # shadows the cache option for this configure only
  # Compile options come after CMAKE_CXX_FLAGS_<CONFIG> on the command line: -O1 wins over -O3.
  add_compile_options(-fsanitize=${lbsolid_sanitize_list} -fno-sanitize-recover=all -fno-omit-frame-pointer -O1 -g)
  # One instruction set (gcc's TSan build compiled the kernels three times); the Release build
  # tests every dispatched path.
  add_compile_definitions(LBSOLID_SINGLE_ISA)
  # Link options: the fuzzer-no-link part only instruments, so it is harmless at link time too.
  add_link_options(-fsanitize=${lbsolid_sanitize_list})
endif()
