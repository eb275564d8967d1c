#include "throng/link/impairment.h"

#include <algorithm>
#include <cmath>

namespace throng::link {

namespace {
bool probability(double p) { return std::isfinite(p) && p >= 0 && p <= 1; }
}  // namespace

std::string check(const ImpairmentConfig& c) {
  if (c.delay.count() < 0 || c.jitter.count() < 0 || c.reorder_gap.count() < 0 || c.queue.count() < 0)
    return "delays, jitter, reorder gap and queue must not be negative";
  if (c.delay > std::chrono::seconds(10) || c.jitter > std::chrono::seconds(10))
    return "delay and jitter must be at most 10 s";
  if (!probability(c.loss)) return "loss must be a probability in [0, 1]";
  if (!probability(c.reorder)) return "reorder must be a probability in [0, 1]";
  const GilbertElliott& b = c.burst;
  if (!probability(b.p_good_to_bad) || !probability(b.p_bad_to_good) || !probability(b.loss_bad) ||
      !probability(b.loss_good))
    return "burst loss parameters must be probabilities in [0, 1]";
  if (b.enabled() && b.p_bad_to_good == 0) return "a burst must end: p(bad->good) must be above 0";
  return {};
}

void DelayHistogram::add(Micros d) {
  const double ms = static_cast<double>(d.count()) / 1000.0;
  const auto bucket = static_cast<std::size_t>(std::max<std::int64_t>(0, d.count()) / 100);
  ++buckets_[std::min(bucket, kBuckets - 1)];
  ++count_;
  sum_ms_ += ms;
  max_ms_ = std::max(max_ms_, ms);
  min_ms_ = std::min(min_ms_, ms);
}

double DelayHistogram::quantile_ms(double q) const {
  if (count_ == 0) return 0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBuckets; ++i) {
    seen += buckets_[i];
    if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(max_ms_, static_cast<double>(i + 1) / 10.0);
  }
  return max_ms_;
}

Impairment::Impairment(ImpairmentConfig config, std::uint64_t seed) : config_(config), rng_(seed) {
  if (config_.reorder_gap.count() == 0) config_.reorder_gap = std::max(Micros(1000), 2 * config_.jitter);
}

double Impairment::uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

Decision Impairment::decide(Micros now, std::size_t bytes) {
  ++counters_.packets;
  counters_.bytes += bytes;
  Decision d;
  // Every draw is made for every packet, whatever is enabled, so one setting never shifts the
  // random stream of another.
  const double u_state = uniform(), u_burst = uniform(), u_loss = uniform(), u_jitter = uniform(),
               u_reorder = uniform();
  const GilbertElliott& ge = config_.burst;
  if (ge.enabled()) {
    bad_ = bad_ ? u_state >= ge.p_bad_to_good : u_state < ge.p_good_to_bad;
    if (u_burst < (bad_ ? ge.loss_bad : ge.loss_good)) d.fate = Fate::lost_burst;
  }
  if (d.fate == Fate::deliver && u_loss < config_.loss) d.fate = Fate::lost_random;

  Micros sent = now;
  if (d.fate == Fate::deliver && config_.rate_bits_per_s > 0) {
    const Micros start = std::max(now, link_free_);
    if (start - now > config_.queue) {
      d.fate = Fate::lost_queue;
    } else {
      link_free_ = start + Micros(static_cast<std::int64_t>(bytes) * 8 * 1'000'000 /
                                  static_cast<std::int64_t>(config_.rate_bits_per_s));
      sent = link_free_;
    }
  }

  if (d.fate != Fate::deliver) {
    if (run_++ == 0) ++counters_.bursts;
    counters_.longest_burst = std::max(counters_.longest_burst, run_);
    switch (d.fate) {
      case Fate::lost_random: ++counters_.lost_random; break;
      case Fate::lost_burst: ++counters_.lost_burst; break;
      case Fate::lost_queue: ++counters_.lost_queue; break;
      case Fate::deliver: break;
    }
    return d;
  }
  run_ = 0;
  const auto j = static_cast<std::int64_t>(std::llround((2 * u_jitter - 1) * static_cast<double>(config_.jitter.count())));
  Micros release = std::max(sent, sent + config_.delay + Micros(j));
  if (u_reorder < config_.reorder) {
    d.reordered = true;
    ++counters_.reordered;
    release += config_.reorder_gap;
  } else {
    release = std::max(release, last_release_);
    last_release_ = release;
  }
  d.release = release;
  ++counters_.delivered;
  delays_.add(release - now);
  return d;
}

}  // namespace throng::link
