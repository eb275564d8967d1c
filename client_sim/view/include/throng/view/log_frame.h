#pragma once
// Log mode: the page's "frame" message built straight from a re-simulated Match (no DDS, no
// snapshots, no interpolation). Every body of the world is sent — a replay has no interest area
// to respect and no bandwidth budget to share — in the same flat [id, x, y, yaw, ...] layout as
// live frames, at full double precision rounded to millimetres, so a test can compare the page's
// positions with a LogPlayer's world.
//
// Yaw: the Match keeps its facing array private (it only leaves the match inside snapshots), so
// the viewer derives it from each body's velocity over the last tick, keeping the previous yaw
// while a body stands still. Right after a seek a standing body shows yaw 0 until it moves.
#include <cstdint>
#include <string>
#include <unordered_map>

#include "throng/match/match.h"

namespace throng::view {

class LogFrameBuilder {
 public:
  // {"type":"frame","mode":"replay",...,"replay":{timeline_fields}}. timeline_fields is
  // LogController::json_fields(); focus (0 = none) is a body whose parameters the frame carries
  // (the character the page follows); pages and input errors as in live frames.
  std::string frame_json(const match::Match& match, const std::string& timeline_fields, std::uint32_t focus,
                         std::size_t pages, std::uint64_t input_errors_total);
  // Forget remembered yaws (after a seek the previous tick is not the one before).
  void reset_yaw() { yaw_.clear(); }

 private:
  std::unordered_map<std::uint32_t, float> yaw_;
};

// {"type":"timeline",...}: the timeline alone, sent when it changes without a new frame (a seek
// starting, pause, speed).
std::string timeline_json(const std::string& timeline_fields);

}  // namespace throng::view
