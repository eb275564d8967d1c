#pragma once
// What one direction of an internet path does to the packets it carries, decided packet by packet
// from a seeded generator, so the same seed and the same arrivals give the same fate to each packet:
//  - loss: random (Bernoulli) and bursty (Gilbert-Elliott: a good and a bad state, each with its
//    own loss probability, and the chances of moving between them per packet);
//  - a bandwidth cap: packets leave at the capped rate, queue behind each other, and are dropped
//    when the queue would hold more than `queue` of sending time (a router's drop-tail buffer);
//  - a one-way delay plus jitter, uniform in [-jitter, +jitter] (never below zero);
//  - order kept: a packet never leaves before one that came in earlier (jitter then shows as
//    bunching, as on a real path), unless reordering is asked for: each packet is then, with that
//    probability, delayed by `reorder_gap` more and let out of order.
#include <chrono>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace throng::link {

using Micros = std::chrono::microseconds;

struct GilbertElliott {
  double p_good_to_bad = 0;  // per packet, in the good state
  double p_bad_to_good = 1;  // per packet, in the bad state (mean burst = 1 / this)
  double loss_bad = 1;
  double loss_good = 0;
  bool enabled() const { return p_good_to_bad > 0; }
};

struct ImpairmentConfig {
  Micros delay{0};
  Micros jitter{0};
  double loss = 0;  // random loss, on top of any burst loss
  GilbertElliott burst;
  double reorder = 0;
  Micros reorder_gap{0};  // 0: twice the jitter, at least 1 ms
  std::uint64_t rate_bits_per_s = 0;  // 0: no cap
  Micros queue{200'000};
};

// "" when the configuration is usable, else what is wrong (probabilities in [0, 1], times >= 0).
std::string check(const ImpairmentConfig& config);

enum class Fate : std::uint8_t { deliver, lost_random, lost_burst, lost_queue };

struct Decision {
  Fate fate = Fate::deliver;
  Micros release{0};  // when it leaves the path (deliver only), on the caller's clock
  bool reordered = false;
};

struct DirectionCounters {
  std::uint64_t packets = 0;
  std::uint64_t bytes = 0;
  std::uint64_t delivered = 0;
  std::uint64_t lost_random = 0;
  std::uint64_t lost_burst = 0;
  std::uint64_t lost_queue = 0;
  std::uint64_t reordered = 0;
  std::uint64_t bursts = 0;  // runs of consecutive lost packets (either loss)
  std::uint64_t longest_burst = 0;
};

// Delays at 0.1 ms resolution up to 20 s (longer ones count in the last bucket): bounded memory
// however long the link runs.
class DelayHistogram {
 public:
  void add(Micros d);
  std::uint64_t count() const { return count_; }
  // The q-quantile (0..1) in milliseconds, at the bucket's upper edge; 0 when empty.
  double quantile_ms(double q) const;
  double mean_ms() const { return count_ == 0 ? 0 : sum_ms_ / static_cast<double>(count_); }
  double max_ms() const { return max_ms_; }
  double min_ms() const { return count_ == 0 ? 0 : min_ms_; }

 private:
  static constexpr std::size_t kBuckets = 200'000;
  std::vector<std::uint32_t> buckets_ = std::vector<std::uint32_t>(kBuckets, 0);
  std::uint64_t count_ = 0;
  double sum_ms_ = 0, max_ms_ = 0, min_ms_ = 1e300;
};

class Impairment {
 public:
  Impairment(ImpairmentConfig config, std::uint64_t seed);

  // The fate of a packet of `bytes` arriving at `now` (a monotonic clock, the caller's).
  Decision decide(Micros now, std::size_t bytes);

  const ImpairmentConfig& config() const { return config_; }
  const DirectionCounters& counters() const { return counters_; }
  // The one-way delays applied to delivered packets (release - arrival).
  const DelayHistogram& delays() const { return delays_; }

 private:
  double uniform();  // [0, 1)

  ImpairmentConfig config_;
  std::mt19937_64 rng_;
  bool bad_ = false;
  Micros link_free_{0};      // the bandwidth cap: when the link has sent what is queued
  Micros last_release_{0};   // order kept: no in-order packet leaves before this
  std::uint64_t run_ = 0;    // the current run of lost packets
  DirectionCounters counters_;
  DelayHistogram delays_;
};

}  // namespace throng::link
