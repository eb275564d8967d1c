// The World-facing half of the residual metrics: reads the world's dense views.
#include <algorithm>
#include <cmath>

#include "throng/scene/residual.h"
#include "throng/world/world.h"

namespace throng::scene {

ResidualStats measure_residual(const World& world) {
  return measure_residual(BodyArrays{world.pos_x(), world.pos_y(), world.pos_z(), world.radius(), world.half_height()});
}

double static_pen_max_over_radius(const World& world) {
  const auto radius = world.radius();
  double worst = 0.0;
  for (std::size_t i = 0; i < radius.size(); ++i) {
    const double pen = world.scenery_max_penetration(i);
    // A NaN body has no meaningful scenery penetration; nan_count reports it instead.
    if (std::isfinite(pen) && radius[i] > 0.0) worst = std::max(worst, pen / radius[i]);
  }
  return worst;
}

}  // namespace throng::scene
