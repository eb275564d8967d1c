#pragma once
// Shared assertions for the geometry tests.
#include <gtest/gtest.h>

#include "throng/core/vec3.h"

namespace throng::geom {

inline void expect_vec(const Vec3& got, const Vec3& want, double tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

}  // namespace throng::geom
