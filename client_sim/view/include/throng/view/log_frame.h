#pragma once
// Log mode: the page's "frame" message built straight from a re-simulated Match (no DDS, no
// snapshots, no interpolation). Every body of the world is sent — a replay has no interest area
// to respect and no bandwidth budget to share — in the same flat [id, x, y, yaw, ...] layout as
// live frames, at full double precision rounded to millimetres, so a test can compare the page's
// positions with a LogPlayer's world.
//
// Yaw: each body's facing as the match keeps it (Match::facing_rad), the same value a live
// client's snapshots carry.
//
// Contacts overlay: while the page asks (LogCommand contacts), frames carry the contact pairs
// nearest the page's camera, chosen from the re-simulated world's push events exactly as the live
// server chooses them (match::ContactSelector, ContactsConfig defaults), in the live frames' form.
#include <cstdint>
#include <optional>
#include <string>

#include "throng/match/contacts.h"
#include "throng/match/match.h"

namespace throng::view {

struct ContactsView {
  double camera_x = 0, camera_y = 0;
};

class LogFrameBuilder {
 public:
  // {"type":"frame","mode":"replay",...,"replay":{timeline_fields}}. timeline_fields is
  // LogController::json_fields(); focus (0 = none) is a body whose parameters the frame carries
  // (the character the page follows); pages and input errors as in live frames; contacts: the
  // overlay's camera when it is on ("contacts" is null otherwise).
  std::string frame_json(const match::Match& match, const std::string& timeline_fields, std::uint32_t focus,
                         std::size_t pages, std::uint64_t input_errors_total,
                         const std::optional<ContactsView>& contacts = std::nullopt);
  // The contact pairs of the match's last tick around (x, y), as frame_json sends them.
  const protocol::ContactPairs& contacts(const match::Match& match, double camera_x, double camera_y);

 private:
  match::ContactSelector selector_;
  protocol::ContactPairs contacts_;
};

// {"type":"timeline",...}: the timeline alone, sent when it changes without a new frame (a seek
// starting, pause, speed).
std::string timeline_json(const std::string& timeline_fields);

}  // namespace throng::view
