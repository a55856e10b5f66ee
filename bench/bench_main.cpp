// bench_main.cpp: the shared main of the Google Benchmark programs: ltm's process set-up
// (malloc tuning) and quiet logging before the benchmarks run.
#include <benchmark/benchmark.h>

#include "ltm/core/log.h"
#include "ltm/core/startup.h"

int main(int argc, char **argv) {
    ltm::configure_process();
    ltm::set_log_level(ltm::LogLevel::quiet);
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    return 0;
}
