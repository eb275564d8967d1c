#include "throng/protocol/codec.h"

#include <cmath>
#include <string>

#include "cdr_size.h"

namespace throng::protocol {

std::optional<std::int16_t> quantize_offset(double v_m, std::int32_t origin_mm, std::uint16_t unit_mm) {
  if (!std::isfinite(v_m) || unit_mm == 0) return std::nullopt;
  const double q = std::nearbyint((v_m * 1000.0 - static_cast<double>(origin_mm)) / unit_mm);
  if (q < -32767.0 || q > 32767.0) return std::nullopt;
  return static_cast<std::int16_t>(q);
}

double dequantize_offset(std::int16_t q, std::int32_t origin_mm, std::uint16_t unit_mm) {
  return (static_cast<double>(origin_mm) + static_cast<double>(q) * unit_mm) / 1000.0;
}

std::uint8_t quantize_yaw(double yaw_rad) {
  if (!std::isfinite(yaw_rad)) return 0;
  const double turns = yaw_rad / (2.0 * kPi);
  const double steps = std::nearbyint((turns - std::floor(turns)) * 256.0);
  return static_cast<std::uint8_t>(static_cast<int>(steps) & 0xFF);
}

double dequantize_yaw(std::uint8_t q) {
  const double yaw = static_cast<double>(q) * (2.0 * kPi / 256.0);
  return yaw > kPi ? yaw - 2.0 * kPi : yaw;
}

bool encode_poses(std::span<const Pose> poses, std::int32_t origin_x_mm, std::int32_t origin_y_mm,
                  std::uint16_t unit_mm, Snapshot& snap) {
  snap.origin_x_mm = origin_x_mm;
  snap.origin_y_mm = origin_y_mm;
  snap.unit_mm = unit_mm;
  snap.id_codes.clear();
  snap.x.clear();
  snap.y.clear();
  snap.z.clear();
  snap.yaw.clear();
  std::uint32_t previous = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Pose& p = poses[i];
    if (i > 0 && p.id <= previous) throw std::invalid_argument("encode_poses: ids must be ascending and unique");
    const auto qx = quantize_offset(p.x, origin_x_mm, unit_mm);
    const auto qy = quantize_offset(p.y, origin_y_mm, unit_mm);
    const auto qz = quantize_offset(p.z, 0, unit_mm);
    if (!qx || !qy || !qz || !std::isfinite(p.yaw)) {
      snap.id_codes.clear();
      snap.x.clear();
      snap.y.clear();
      snap.z.clear();
      snap.yaw.clear();
      return false;
    }
    const std::uint32_t delta = p.id - previous;
    if (delta >= 1 && delta <= 0xFFFF) {
      snap.id_codes.push_back(static_cast<std::uint16_t>(delta));
    } else {
      snap.id_codes.push_back(0);
      snap.id_codes.push_back(static_cast<std::uint16_t>(p.id >> 16));
      snap.id_codes.push_back(static_cast<std::uint16_t>(p.id & 0xFFFF));
    }
    previous = p.id;
    snap.x.push_back(*qx);
    snap.y.push_back(*qy);
    snap.z.push_back(*qz);
    snap.yaw.push_back(quantize_yaw(p.yaw));
  }
  share_equal_heights(snap);
  return true;
}

void share_equal_heights(Snapshot& snap) {
  const auto& z = snap.z;
  if (z.size() < 2) return;
  for (std::size_t i = 1; i < z.size(); ++i)
    if (z[i] != z[0]) return;
  snap.z.erase(snap.z.begin() + 1, snap.z.end());  // (resize(1) trips GCC 12's -Warray-bounds)
}

void decode_poses(const Snapshot& snap, std::vector<Pose>& out) {
  const std::size_t n = snap.x.size();
  const bool shared_z = n >= 1 && snap.z.size() == 1;  // one height for every pose
  if (snap.y.size() != n || (snap.z.size() != n && !shared_z) || snap.yaw.size() != n)
    throw DecodeError("snapshot: pose arrays differ in length (x " + std::to_string(n) + ", y " +
                      std::to_string(snap.y.size()) + ", z " + std::to_string(snap.z.size()) + ", yaw " +
                      std::to_string(snap.yaw.size()) + ")");
  if (n > 0 && snap.unit_mm == 0) throw DecodeError("snapshot: unit_mm is 0");
  std::uint32_t previous = 0;
  std::size_t c = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (c >= snap.id_codes.size()) throw DecodeError("snapshot: fewer id codes than poses");
    std::uint32_t id;
    if (snap.id_codes[c] != 0) {
      id = previous + snap.id_codes[c];
      if (id < previous) throw DecodeError("snapshot: id code overflows at pose " + std::to_string(i));
      c += 1;
    } else {
      if (c + 2 >= snap.id_codes.size()) throw DecodeError("snapshot: truncated id escape at pose " + std::to_string(i));
      id = (static_cast<std::uint32_t>(snap.id_codes[c + 1]) << 16) | snap.id_codes[c + 2];
      if (i > 0 && id <= previous) throw DecodeError("snapshot: ids not ascending at pose " + std::to_string(i));
      c += 3;
    }
    previous = id;
    out.push_back(Pose{id, dequantize_offset(snap.x[i], snap.origin_x_mm, snap.unit_mm),
                       dequantize_offset(snap.y[i], snap.origin_y_mm, snap.unit_mm),
                       dequantize_offset(snap.z[shared_z ? 0 : i], 0, snap.unit_mm), dequantize_yaw(snap.yaw[i])});
  }
  if (c != snap.id_codes.size()) throw DecodeError("snapshot: more id codes than poses");
}


std::size_t snapshot_wire_bytes(const Snapshot& s) {
  detail::CdrSize c;
  c.prim(4);  // client_id
  c.prim(8);  // tick
  c.prim(4);  // last_applied_sequence
  c.prim(8);  // last_applied_tick
  c.prim(4);  // entity
  for (int i = 0; i < 4; ++i) c.prim(4);  // own pose
  c.prim(4);
  c.prim(4);  // origin
  c.prim(2);  // unit_mm
  c.prim(4);  // objects_in_view
  c.seq(s.id_codes.size(), 2);
  c.seq(s.x.size(), 2);
  c.seq(s.y.size(), 2);
  c.seq(s.z.size(), 2);
  c.seq(s.yaw.size(), 1);
  c.seq(s.removed.size(), 4);
  return c.n + 4;  // + the 4-byte encapsulation header
}


}  // namespace throng::protocol
