#pragma once
// Exact upright-capsule vs upright-box / upright-cylinder penetration (private).
#include "scenery_shapes.h"

namespace throng::geom::detail {

SignedPenetration upright_capsule_vs_box(const UprightCore& core, const BoxShape& box);
SignedPenetration upright_capsule_vs_cylinder(const UprightCore& core, const CylinderShape& cyl);

}  // namespace throng::geom::detail
