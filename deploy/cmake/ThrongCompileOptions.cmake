# Compile options for Throng's own targets (never for third-party code).
#
# Determinism: the simulation must give bit-identical state for the same inputs and binary, so
# floating point contraction (FMA fusion) is off and nothing enables -ffast-math. We do not pass
# -march=native either: CI and developer machines may differ, and the stored golden hashes must hold
# on any x86-64 machine that runs the same code.
set(THRONG_WARNINGS -Wall -Wextra -Werror -Wshadow -Wnon-virtual-dtor -Wpedantic)
set(THRONG_FP_FLAGS -ffp-contract=off -fno-fast-math)

set(THRONG_SANITIZE_FLAGS "")
if(THRONG_SANITIZE)
  set(THRONG_SANITIZE_FLAGS -fsanitize=${THRONG_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  # GCC 12's -Wmaybe-uninitialized gives false positives inside libstdc++ (std::function in
  # std::regex) once ASan instruments the code at -O2; the Release build keeps the warning on, so
  # real cases are still caught there.
  list(APPEND THRONG_WARNINGS -Wno-maybe-uninitialized)
endif()

# THRONG_FUZZ: every library is instrumented for libFuzzer's coverage (fuzzer-no-link) plus ASan and
# UBSan; the fuzz targets themselves link with -fsanitize=fuzzer (tests/fuzz/CMakeLists.txt). -O1
# and assertions on (deploy/fuzz.sh configures CMAKE_BUILD_TYPE=Fuzz, which adds no flags): fast
# enough to fuzz, and an assert that fires is a finding. Line tables only: enough for the
# sanitizers' stack traces, and much cheaper to compile than full debug information.
if(THRONG_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "THRONG_FUZZ needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  if(THRONG_SANITIZE)
    message(FATAL_ERROR "THRONG_FUZZ sets its own sanitizers; leave THRONG_SANITIZE empty")
  endif()
  set(THRONG_SANITIZE_FLAGS -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                            -fno-sanitize-recover=all -O1 -gline-tables-only)
endif()

function(throng_target_defaults target)
  target_compile_options(${target} PRIVATE ${THRONG_WARNINGS} ${THRONG_FP_FLAGS} ${THRONG_SANITIZE_FLAGS})
  target_compile_features(${target} PUBLIC cxx_std_20)
  if(THRONG_SANITIZE)
    target_link_options(${target} PRIVATE ${THRONG_SANITIZE_FLAGS})
  endif()
endfunction()
