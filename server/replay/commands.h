#pragma once
// throng-replay's subcommands. Each returns the process exit code:
//   0  success (verify: every readable tick's hash matched; a torn tail is reported, not an error)
//   1  verify/export/play: the re-simulation diverged from the logged hashes
//   2  usage error, unreadable file, not a match log, unsupported version, bad header
//   3  the log is damaged in the middle or has ticks the writer dropped: read/verified up to there
#include <cstdint>
#include <string>

namespace throng::replay {

inline constexpr int kExitOk = 0;
inline constexpr int kExitMismatch = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitDamaged = 3;

struct InfoOptions {
  std::string log;
  bool json = false;
};
int run_info(const InfoOptions& o);

struct VerifyOptions {
  std::string log;
  bool quiet = false;  // no progress line
  bool exact_config = false;  // replay with the logged interest settings (ResimOptions::exact_interest)
  unsigned jobs = 0;          // threads for a log with keyframes; 0 = hardware threads
};
int run_verify(const VerifyOptions& o);

struct SeekOptions {
  std::string log;
  std::uint64_t tick = 0;
  bool json = false;
};
int run_seek(const SeekOptions& o);

struct ExportOptions {
  std::string log;
  std::uint64_t from = 1;
  std::uint64_t to = 0;  // 0 = from
  std::string format = "csv";
  std::string out;       // "" = stdout
  bool poses = true;
  bool pushes = true;
  bool quiet = false;
  bool exact_config = false;
};
int run_export(const ExportOptions& o);

// play: re-publish a logged match over DDS (play.cpp; watchers as spectators: play_watchers.h).
struct PlayOptions {
  std::string log;
  double speed = 1.0;           // 0.1..16: ticks run at tick_hz * speed
  std::uint64_t from = 1;       // first tick published (the player re-simulates up to from - 1 first)
  int domain = 0;               // DDS domain, like throng-server
  bool network = false;         // Fast DDS's default transports instead of 127.0.0.1 only
  std::string listen;           // tcp://ADDR:PORT: DDS over TCP only, as throng-server --listen
  std::string security_dir;     // DDS Security with the server identity of this throng-pki directory
  bool loop = false;            // at the end, seek back to --from and play again (until a signal)
  bool strict = false;          // stop at the first tick whose hash differs from the log
  std::uint32_t max_watchers = 64;
  double watcher_timeout_s = 10.0;  // a watcher that sends no command for this long is dropped; 0 = never
  bool quiet = false;           // no progress line
};
int run_play(const PlayOptions& o);

// Progress on stderr: one rewriting line on a terminal, a line every 10% otherwise.
class Progress {
 public:
  Progress(const char* what, bool enabled);
  void update(std::uint64_t done, std::uint64_t total);
  void finish();

 private:
  const char* what_;
  bool enabled_, tty_;
  int last_decile_ = -1;
  double start_s_;
  double last_print_s_ = -1.0;
};

}  // namespace throng::replay
