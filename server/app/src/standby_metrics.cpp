#include "throng/server/standby_metrics.h"

#include "throng/server/standby_server.h"

namespace throng::server {
StandbyMetrics::StandbyMetrics(admin::MetricsRegistry& r)
    : following(r.gauge("throng_standby_following",
                        "1 while the standby holds the primary's match and every applied tick matched its state hash.")),
      tick(r.gauge("throng_standby_tick", "The last tick the standby applied.")),
      primary_tick(r.gauge("throng_standby_primary_tick", "The newest tick entry received from the primary.")),
      ticks_applied(r.counter("throng_standby_ticks_applied_total", "Ticks applied with the primary's state hash.")),
      mismatches(r.counter("throng_standby_mismatches_total",
                           "Ticks whose state hash differed from the primary's (each makes the standby ask for the match again).")),
      checkpoints(r.counter("throng_standby_checkpoints_total", "Checkpoints of the primary's match restored.")),
      gaps(r.counter("throng_standby_gaps_total", "Tick entries that arrived after a missing one.")),
      entries_refused(r.counter("throng_standby_entries_refused_total", "Malformed tick entries refused.")) {}

void StandbyMetrics::update(const StandbyStatus& s, const StandbyTotals& earlier) {
  following.set(s.synced && s.following ? 1.0 : 0.0);
  tick.set(static_cast<double>(s.tick));
  primary_tick.set(static_cast<double>(s.primary_tick));
  ticks_applied.raise_to(earlier.applied + s.follower.applied);
  mismatches.raise_to(earlier.mismatches + s.follower.mismatches);
  checkpoints.raise_to(earlier.checkpoints + s.follower.checkpoints);
  gaps.raise_to(earlier.gaps + s.follower.gaps);
  entries_refused.raise_to(s.entries_refused);
}

}  // namespace throng::server
