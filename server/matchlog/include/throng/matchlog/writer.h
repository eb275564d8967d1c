#pragma once
// MatchLogWriter: records a match while it runs, without ever making the tick wait for the disk.
//
// How the server uses it (all calls from the tick thread):
//
//   matchlog::MatchLogWriter log("logs/<match_id>.tlog");         // nothing touches the disk yet
//   matchlog::LogHeader header;          // build_id: "" = default_build_id() (git describe + date)
//   header.match_id = match_id;          // the same id, SceneDef and MatchConfig the Match was
//   header.scene = scene;                //   built with (the scaled scene)
//   header.config = config;
//   log.begin(header);  // writes + syncs the header, starts the writer thread; throws LogError
//                       // (cannot create the file or its folder, unreadable scene params file)
//   // every tick:
//   std::uint8_t flags = shutdown_called_before_this_tick ? matchlog::kTickShutdownBegan : 0;
//   const auto& r = match.tick(outbox);
//   log.append_tick(r.tick, match.last_inputs(), r.state_hash, flags);   // never blocks, never throws
//   if (r.tick % log.keyframe_interval_ticks() == 0) {   // a world keyframe every ~2 s (format v2)
//     match.save_checkpoint(buffer);                     // reused buffer: no allocation once warm
//     log.append_keyframe_swap(r.tick, buffer);          // O(1); dropped (counted) if the writer is behind
//   }
//   // once a second (e.g. with the other metrics):
//   const matchlog::WriterStats s = log.stats();  // backlog, drops, I/O error -> metric + log line
//   // at the end (after the final tick):
//   log.close();  // drains the queue, writes the final index and end record, fsyncs, joins the thread
//                 // (throws LogError if a write/fsync failed during the match)
//
// append_tick() serialises the tick's inputs into a slot of a pre-allocated ring (microseconds;
// no allocation once the slots have grown to the busiest tick) and returns; it never wakes the
// writer thread (the woken writer preempted the tick: docs/design/match-log.md). The writer
// thread (SCHED_BATCH) polls every poll_ms,
// groups ticks into blocks of block_ticks (aligned on tick numbers, so the file's content is a
// function of the inputs only), compresses each block with zstd, frames it with a CRC32C, writes
// it, and fdatasyncs at most fsync_interval_ms after a write.
//
// stats().backlog_ticks counts ticks appended but not yet handed to the OS, the block being
// filled included (so up to block_ticks - 1 + poll_ms worth of ticks is normal). Signs of a disk
// that cannot keep up: spilled_ticks growing (the ring is full), ticks_dropped > 0, io_error.
//
// If the disk cannot keep up and the ring is full, ticks go to an unbounded-in-principle spill
// list capped at spill_cap_bytes (allocations, but still no waiting). Beyond the cap a tick is
// dropped: counted in stats().ticks_dropped and marked in the file by a gap record, so a reader
// knows exactly which ticks are missing. Nothing is ever dropped silently; the server must report
// stats().backlog_ticks / ticks_dropped / io_error loudly.
//
// What a crash can cost (defaults, 30 Hz):
//   kill -9 of the server:  the ticks of the current, incomplete block (at most block_ticks - 1 =
//                           14 ticks, 0.47 s) plus any backlog; everything written before is in the
//                           page cache and survives.
//   power loss / kernel panic: additionally what was written but not yet fsynced: at most
//                           fsync_interval_ms (1 s = 30 ticks) -> at most 44 ticks (~1.5 s) plus
//                           backlog.
// The reader recovers every complete tick before the damage ("torn tail") either way.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "throng/match/input_queue.h"
#include "throng/matchlog/format.h"
#include "throng/matchlog/log_header.h"

namespace throng::matchlog {

struct WriterOptions {
  std::uint32_t block_ticks = 15;           // ticks per tick-block record [1, 4096]
  std::uint32_t index_interval_ticks = 60;  // an index record every this many ticks (rounded up to a
                                            //   multiple of block_ticks; ~2 s at 30 Hz)
  int zstd_level = 1;                       // 0 = store blocks raw; 1..19 zstd level (1 was both
                                            //   smaller and faster than 3 on battle inputs)
  std::uint32_t fsync_interval_ms = 1000;   // fdatasync at most this long after a write; 0 = after
                                            //   every record
  std::uint32_t ring_slots = 512;           // pre-allocated tick slots (17 s at 30 Hz)
  std::size_t slot_reserve_bytes = 8192;    // initial capacity of each slot (150 commands)
  std::size_t spill_cap_bytes = 256u << 20; // beyond the ring: at most this much backlog, then drop
  std::uint32_t poll_ms = 50;               // the writer thread looks for new ticks this often (the
                                            //   tick thread never wakes it: see writer.cpp)
  // World keyframes (format version 2): the caller hands Match::save_checkpoint() bytes to
  // append_keyframe() after every tick that is a multiple of this (rounded up to a multiple of
  // block_ticks; default = the index interval, ~2 s at 30 Hz). 0 = no keyframes.
  std::uint32_t keyframe_interval_ticks = 60;
  std::uint32_t keyframe_slots = 2;          // keyframes waiting for the writer thread; beyond: dropped
  // Whether the caller's keyframes hold the snapshot baselines (match::SaveOptions), recorded in
  // the header so `play` can say what a seek gives. The writer does not look inside keyframes.
  bool keyframe_snapshot_baselines = false;
  // Tests only: sleep this long after every write, to simulate a slow disk. 0 in production.
  std::uint32_t test_write_delay_ms = 0;
};

struct WriterStats {
  std::uint64_t ticks_appended = 0;   // append_tick calls
  std::uint64_t ticks_written = 0;    // ticks handed to the OS (write returned)
  std::uint64_t ticks_dropped = 0;    // lost to the spill cap or an I/O error (never silently: see gap records)
  std::uint64_t backlog_ticks = 0;    // appended but not yet written or dropped
  std::uint64_t backlog_high_water = 0;
  std::uint64_t spilled_ticks = 0;    // ticks that did not fit the ring (disk slower than the match)
  std::size_t spill_bytes = 0;        // bytes in the spill list now
  std::uint64_t bytes_written = 0;    // file size so far
  std::uint64_t raw_tick_bytes = 0;   // tick entries before compression
  std::uint64_t records = 0;
  std::uint64_t fsyncs = 0;
  // Times the writer thread had nothing left to do and went to sleep until the next poll: lets a
  // test wait for it to be idle instead of guessing with a sleep.
  std::uint64_t writer_sleeps = 0;
  double max_fsync_ms = 0;
  double max_append_us = 0;
  double p99_append_us = 0;           // from a 0.1 µs histogram up to 100 µs (beyond: max)
  std::string io_error;               // first write/fsync error ("" = none); logging stopped there
  // Keyframes (append_keyframe)
  std::uint64_t keyframes_appended = 0;
  std::uint64_t keyframes_written = 0;
  std::uint64_t keyframes_dropped = 0;   // the writer was behind (slots full) or the tick was dropped
  std::uint64_t keyframe_bytes = 0;      // framed keyframe records in the file
  std::uint64_t keyframe_raw_bytes = 0;  // the same checkpoints uncompressed
  double max_keyframe_append_us = 0;     // the copy into a slot, on the tick thread
  // The most block and keyframe entries the writer held in memory at once: those since the last
  // periodic index record, so bounded by the index interval, not by the match's length.
  std::uint64_t index_entries_high_water = 0;
};

class MatchLogWriter {
 public:
  explicit MatchLogWriter(std::string path, WriterOptions options = {});
  ~MatchLogWriter();  // close(), errors swallowed (call close() yourself to see them)
  MatchLogWriter(const MatchLogWriter&) = delete;
  MatchLogWriter& operator=(const MatchLogWriter&) = delete;

  // Creates the file (and its parent folders; an existing file is replaced), writes the preamble
  // and the header record, fsyncs, and starts the writer thread. Fills format_version, start time,
  // scene hash and writer settings; inlines parameter/policy files (self_contained_scene). Throws
  // LogError on any problem (bad options, cannot create, cannot read a scene file).
  void begin(LogHeader header);
  // A log that starts after tick `tick` of a match rather than before tick 1 (a hot standby's, and
  // the match it may take over): begin(), then a gap record for ticks 1..tick (reason: started
  // from a checkpoint) and `checkpoint` (Match::save_checkpoint after `tick`) as the keyframe of
  // `tick`, written before this returns; append_tick then expects tick + 1. verify and seek start
  // from that keyframe. tick >= 1.
  void begin_from(LogHeader header, std::uint64_t tick, const std::vector<std::uint8_t>& checkpoint);

  // Ticks must be 1, 2, 3, ... (std::invalid_argument otherwise: a programming error). Never blocks
  // on I/O and never throws for I/O problems.
  void append_tick(std::uint64_t tick, const match::TickInputs& inputs, std::uint64_t state_hash,
                   std::uint8_t flags = 0);

  // A world keyframe for the last appended tick (which must be a multiple of the keyframe
  // interval, std::invalid_argument otherwise): Match::save_checkpoint() bytes, copied into a
  // writer-owned slot (reused; allocates only while a slot grows) and returns. Never blocks: when
  // every slot is still waiting for the writer thread, the keyframe is dropped and counted in
  // stats().keyframes_dropped (a missing keyframe only makes seeking slower; report it). The file
  // stays a function of the inputs: the keyframe is written right after the block ending at its tick.
  void append_keyframe(std::uint64_t tick, std::span<const std::uint8_t> checkpoint);
  // The same without the copy (a large match's checkpoint is megabytes; copying it on the tick
  // thread costs a sizeable part of a tick: docs/design/match-log.md): the
  // checkpoint's buffer is swapped with the slot's, so on return `checkpoint` holds an older buffer
  // (contents unspecified, capacity kept) for the next save_checkpoint, which then does not
  // allocate either. O(1) on the tick thread. Dropped: `checkpoint` is left as it was.
  void append_keyframe_swap(std::uint64_t tick, std::vector<std::uint8_t>& checkpoint);
  std::uint32_t keyframe_interval_ticks() const { return opt_.keyframe_interval_ticks; }  // after rounding
  std::uint64_t next_tick() const { return next_tick_; }  // the tick append_tick expects (the tick thread's)
  const WriterOptions& options() const { return opt_; }  // as used (intervals rounded)

  // Waits for the writer thread to write everything queued, then writes the final (partial) block,
  // the final index and the end record, fsyncs and closes the file. Idempotent. Throws LogError if
  // any write or fsync failed during the match (the message says which and where).
  void close();

  WriterStats stats() const;  // any thread
  const std::string& path() const { return path_; }
  bool is_open() const { return began_ && !closed_; }

 private:
  struct Slot {
    std::vector<std::uint8_t> bytes;
  };
  struct KeyframeSlot {
    std::uint64_t tick = 0;
    std::vector<std::uint8_t> bytes;
  };
  void start(LogHeader header, std::uint64_t base_tick, const std::vector<std::uint8_t>* checkpoint);
  void run();
  bool process_one();
  void consume(const std::vector<std::uint8_t>& entry);
  void flush_block();
  void write_gap(std::uint64_t first, std::uint64_t count, std::uint8_t reason = kGapDropped);
  void write_index(bool final);
  bool resolve_keyframe();  // writer thread: the keyframe decision for kf_pending_ is known
  KeyframeSlot* keyframe_slot(std::uint64_t tick);  // tick thread: a free slot, or nullptr (dropped, counted)
  void publish_keyframe(std::chrono::steady_clock::time_point t0);
  void write_keyframe(std::uint64_t tick, const std::vector<std::uint8_t>& bytes);
  void write_record(RecordType type, const std::vector<std::uint8_t>& payload);
  void maybe_fsync(bool force);
  void fail_io(const std::string& what);

  std::string path_;
  WriterOptions opt_;
  int fd_ = -1;
  bool began_ = false, closed_ = false;
  std::uint64_t next_tick_ = 1;  // tick thread: the tick append_tick expects
  std::uint64_t base_tick_ = 0;  // the log starts after this tick (begin_from); appended_ counts from it
  bool last_tick_dropped_ = false;  // tick thread: the last append_tick dropped its tick

  // keyframe slots (single producer: tick thread, single consumer: writer thread)
  std::vector<KeyframeSlot> kf_ring_;
  std::atomic<std::uint64_t> kf_head_{0}, kf_tail_{0};

  // ring (single producer: tick thread, single consumer: writer thread)
  std::vector<Slot> ring_;
  std::atomic<std::uint64_t> head_{0}, tail_{0};
  // spill (both threads, under spill_mutex_)
  mutable std::mutex spill_mutex_;
  std::deque<std::vector<std::uint8_t>> spill_;
  std::atomic<std::size_t> spill_bytes_{0};
  std::atomic<std::size_t> spill_count_{0};

  std::thread thread_;
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  std::atomic<bool> closing_{false};

  // writer-thread state
  std::vector<std::uint8_t> block_raw_, block_payload_, compressed_, record_;
  std::uint64_t block_first_ = 0, block_count_ = 0, block_window_ = 0;
  std::uint64_t expected_tick_ = 1;  // next tick the file should hold
  struct IndexEntry {
    std::uint64_t first_tick, offset;
    std::uint32_t tick_count;
  };
  // The blocks and keyframes written since the last periodic index record. Those before it are in
  // the file, and the final index reads them back (read_published_index): held here, they grew
  // with the match (a block every half second) for as long as it ran.
  std::vector<IndexEntry> index_unpublished_;
  struct KeyframeEntry {
    std::uint64_t tick, offset;
  };
  std::vector<KeyframeEntry> kf_unpublished_;
  bool read_published_index(std::vector<IndexEntry>& blocks, std::vector<KeyframeEntry>& keyframes);
  std::uint64_t kf_pending_ = 0;     // a block ending at this keyframe tick was written; its keyframe is not decided yet
  std::vector<std::uint8_t> kf_payload_;
  std::uint64_t last_index_offset_ = 0;
  std::uint64_t offset_ = 0;         // file size
  std::uint64_t unsynced_bytes_ = 0;
  std::chrono::steady_clock::time_point last_sync_{};
  void* zctx_ = nullptr;             // ZSTD_CCtx
  std::atomic<bool> io_failed_{false};

  // stats
  std::atomic<std::uint64_t> appended_{0}, written_{0}, dropped_{0}, spilled_{0};
  std::atomic<std::uint64_t> backlog_high_{0};
  std::atomic<std::uint64_t> bytes_{0}, raw_bytes_{0}, records_{0}, fsyncs_{0};
  std::atomic<std::uint64_t> sleeps_{0};
  std::atomic<std::uint64_t> max_fsync_ns_{0}, max_append_ns_{0};
  std::atomic<std::uint64_t> kf_appended_{0}, kf_written_{0}, kf_dropped_{0}, kf_bytes_{0}, kf_raw_bytes_{0}, max_kf_append_ns_{0};
  std::atomic<std::uint64_t> index_held_high_{0};
  static constexpr std::size_t kHistBins = 1000;  // 0.1 µs bins, 0..100 µs
  std::unique_ptr<std::atomic<std::uint32_t>[]> hist_;
  std::atomic<std::uint64_t> hist_over_{0};
  mutable std::mutex error_mutex_;
  std::string io_error_;
};

}  // namespace throng::matchlog
