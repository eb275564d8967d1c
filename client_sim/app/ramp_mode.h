#pragma once
// Ramp mode: start with ramp_start bots, hold each client count for a measuring window, read the
// server's ServerStats (tick overruns, tick p99) and the bots' missed snapshots, add ramp_step bots
// and repeat; stop at the first failing step or at ramp_max.
#include <atomic>

#include "options.h"
#include "progress.h"
#include "throng/client_sim/fleet.h"
#include "throng/client_sim/ramp.h"

namespace throng::bots {

client_sim::RampResult run_ramp(client_sim::Fleet& fleet, const Options& options, const std::atomic<bool>& stop,
                                ProgressLine& progress);

}  // namespace throng::bots
