// throng-microbench entry point (benchmarks are registered by the other files in this folder).
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
