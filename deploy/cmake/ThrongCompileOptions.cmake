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

function(throng_target_defaults target)
  target_compile_options(${target} PRIVATE ${THRONG_WARNINGS} ${THRONG_FP_FLAGS} ${THRONG_SANITIZE_FLAGS})
  target_compile_features(${target} PUBLIC cxx_std_20)
  if(THRONG_SANITIZE)
    target_link_options(${target} PRIVATE ${THRONG_SANITIZE_FLAGS})
  endif()
endfunction()
