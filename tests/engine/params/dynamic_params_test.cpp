#include "throng/params/dynamic_params.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace throng::params {
namespace {

TEST(ParamsDynamic, SpeedAndFacingFromVelocity) {
  EXPECT_DOUBLE_EQ(speed_from_velocity(3.0, 4.0, 0.0), 5.0);
  EXPECT_DOUBLE_EQ(speed_from_velocity(0.0, 0.0, -2.0), 2.0);
  EXPECT_EQ(speed_from_velocity(1e9, 0.0, 0.0), kMaxSpeed_mps);
  const Facing f = facing_from_velocity(3.0, 4.0, {1.0, 0.0});
  EXPECT_DOUBLE_EQ(f.x, 0.6);
  EXPECT_DOUBLE_EQ(f.y, 0.8);
  // Standing still (or only falling) keeps the previous facing.
  const Facing keep = facing_from_velocity(kMinFacingSpeed_mps / 2.0, 0.0, {0.0, -1.0});
  EXPECT_EQ(keep.x, 0.0);
  EXPECT_EQ(keep.y, -1.0);
}

TEST(ParamsDynamic, ApplyVelocityWritesValidatedFields) {
  ObjectParams o;
  apply_velocity(o, 0.0, -2.0, 0.0);
  EXPECT_DOUBLE_EQ(o.speed_mps, 2.0);
  EXPECT_DOUBLE_EQ(o.facing_x, 0.0);
  EXPECT_DOUBLE_EQ(o.facing_y, -1.0);
  EXPECT_NO_THROW(o.validate());
  EXPECT_THROW(apply_velocity(o, std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(apply_velocity(o, std::numeric_limits<double>::infinity(), 0.0, 0.0), std::invalid_argument);
}

TEST(ParamsDynamic, CameraDistanceIsTheNearestCappedDistance) {
  const std::vector<std::array<double, 3>> cams = {{10.0, 0.0, 0.0}, {0.0, 3.0, 4.0}, {-50.0, 0.0, 0.0}};
  EXPECT_DOUBLE_EQ(camera_distance_m(cams, 0.0, 0.0, 0.0), 5.0);
  EXPECT_EQ(camera_distance_m({}, 1.0, 2.0, 3.0), kCameraDistanceCap_m);
  const std::vector<std::array<double, 3>> far = {{2.0 * kCameraDistanceCap_m, 0.0, 0.0}};
  EXPECT_EQ(camera_distance_m(far, 0.0, 0.0, 0.0), kCameraDistanceCap_m);
  ObjectParams o;
  EXPECT_NO_THROW(o.set(Param::camera_distance_m, camera_distance_m({}, 0.0, 0.0, 0.0)));
}

TEST(ParamsDynamic, HeightAboveGround) {
  EXPECT_DOUBLE_EQ(height_above_ground_m(12.5, 10.0), 2.5);
  EXPECT_DOUBLE_EQ(height_above_ground_m(9.0, 10.0), -1.0);
}

}  // namespace
}  // namespace throng::params
