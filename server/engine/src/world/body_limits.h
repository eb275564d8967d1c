#pragma once
// What the public API lets a body be: create_body and set_desired_velocity enforce these, and a
// checkpoint's decoder refuses a body outside them (no call could have made it).
namespace throng::detail {

inline constexpr double kMinBodyRadiusM = 1e-4;
inline constexpr double kMaxBodyRadiusM = 100.0;
inline constexpr double kMaxBodyHalfHeightM = 100.0;
inline constexpr double kMaxDesiredSpeedMps = 1000.0;
// A body's reach: its radius plus the contact margin (WorldSettings: at most 10 m).
inline constexpr double kMaxBodyReachM = kMaxBodyRadiusM + 10.0;

}  // namespace throng::detail
