#pragma once
// Saves the match log's world keyframes (Match::save_checkpoint) on a thread of its own, so the
// save — milliseconds with many clients' snapshot baselines (docs/design/match-log.md) — does not
// lengthen the tick it belongs to.
//
// Why this is safe: save_checkpoint is const, and between two tick() calls the match is only read
// (publish_outbox, metrics). The tick thread starts a save right after a keyframe tick and calls
// finish() before the next tick() mutates the match; the save has the whole tick period (33 ms at
// 30 Hz) to complete, so finish() normally returns at once. Keyframes therefore still land in the
// log right after their own tick's record and before the next one's.
#include <condition_variable>
#include <exception>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace throng::match {
class Match;
}

namespace throng::server {

class KeyframeSaver {
 public:
  struct Finished {
    std::uint64_t tick = 0;         // the keyframe's tick
    std::vector<std::uint8_t>* bytes = nullptr;  // the checkpoint; valid until the next start()
    double save_seconds = 0.0;      // time save_checkpoint took on the saver thread
    double waited_seconds = 0.0;    // time finish() blocked the caller
  };

  // with_snapshot_baselines: whether the keyframes keep the snapshot baselines (match::SaveOptions;
  // the server's --log-baselines).
  explicit KeyframeSaver(bool with_snapshot_baselines);
  ~KeyframeSaver();  // waits for a save in progress, then stops the thread
  KeyframeSaver(const KeyframeSaver&) = delete;
  KeyframeSaver& operator=(const KeyframeSaver&) = delete;

  // Starts saving `match` as the keyframe of `tick`. The match must not be mutated until finish()
  // returned. Throws std::logic_error if a save is still pending (finish() it first).
  void start(const match::Match& match, std::uint64_t tick);
  bool pending() const { return pending_; }
  // Blocks until the pending save is done. Returns false (and leaves `out` alone) with nothing
  // pending. A save that threw is rethrown here, on the caller's thread.
  bool finish(Finished& out);

 private:
  void run();

  std::mutex mutex_;
  std::condition_variable cv_;
  const match::Match* match_ = nullptr;  // set while a save is requested or running
  std::uint64_t tick_ = 0;
  const bool with_snapshot_baselines_;
  bool requested_ = false, done_ = false, stopping_ = false;
  bool pending_ = false;  // tick thread only: start() without finish()
  double save_seconds_ = 0.0;
  std::exception_ptr error_;
  std::vector<std::uint8_t> buffer_;  // reused: a warm buffer does not allocate
  std::thread thread_;
};

}  // namespace throng::server
