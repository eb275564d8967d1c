#pragma once
// The human-readable summary of one run (the --json form is to_json in run_scene.h).
#include <cstdio>

#include "run_scene.h"

namespace throng::bench {

void print_summary(std::FILE* out, const RunResult& r);

}  // namespace throng::bench
