#pragma once
// Validation of the closed-form capsule contact against the long-double reference and FCL 0.7,
// over the pair families of capsule_pair_generator.h. Used by the GoogleTest suite (which asserts
// the closed-form bounds) and by the bench (which prints the report).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "throng/geometry/capsule_pair_generator.h"

namespace throng::geom {

// Closed-form |distance error| must stay below this times max(1, largest |coordinate|).
inline constexpr double kClosedFormRelativeBound = 1e-9;
// FCL failure thresholds (FCL is reported, not asserted).
inline constexpr double kFclDistanceTolerance = 1e-6;  // m, FCL's own default GJK tolerance
inline constexpr double kFclDepthTolerance = 1e-4;     // m
inline constexpr double kFclNormalTolerance = 1e-3;    // rad
inline constexpr double kVerdictMargin = 1e-9;         // m; touching pairs may go either way

struct ErrorStats {
  std::size_t count = 0;
  double max = 0.0;
  double p99 = 0.0;
  double median = 0.0;
};

// fcl::collide with contacts, one solver.
struct FclCollideStats {
  std::size_t compared = 0;        // pairs both FCL and the reference call penetrating
  ErrorStats depth_error;          // |FCL penetration_depth - exact depth|, m (raw FCL value)
  ErrorStats abs_depth_error;      // ||FCL depth| - exact depth|: the magnitude, whatever the sign
  ErrorStats normal_error;         // angle to the exact normal, rad, where that normal is unique
  ErrorStats axis_error;           // the same, ignoring the normal's sign
  std::size_t not_separating = 0;  // moving b by depth * normal leaves > kFclDepthTolerance overlap
  std::size_t wrong_sign = 0;      // collision verdict wrong beyond kVerdictMargin, or depth < 0
  std::size_t bad_depth = 0;       // depth error > kFclDepthTolerance
  std::size_t bad_normal = 0;      // normal error > kFclNormalTolerance
  std::size_t failed_pairs = 0;    // pairs with any of the three
};

struct FamilyValidation {
  PairFamily family = PairFamily::kGeneric;
  std::string name;
  std::size_t pairs = 0;
  std::size_t penetrating = 0;  // by the reference

  // Closed form vs long-double reference.
  ErrorStats closed_distance;  // m
  ErrorStats closed_normal;    // rad; sign-agnostic against axis_a x axis_b for crossing cores
  double closed_max_scaled_error = 0;  // max of |error| / max(1, |coordinates|)
  std::size_t closed_bound_violations = 0;
  std::size_t closed_bad_output = 0;  // non-finite distance or non-unit normal

  // FCL vs the same reference.
  // fcl::distance (default request: libccd, unsigned, which for capsule/sphere pairs is FCL's
  // analytic segment code) on the pairs the reference calls separated. The signed variant is not
  // run: FCL 0.7 sends every pair through libccd GJK/EPA there, which aborts on an assertion
  // (ComputeVisiblePatch: isOutsidePolytopeFace) for touching pairs and takes seconds to forever
  // for overlapping spheres (0.27 s at 1 cm centre distance, > 5 s at 1 mm, no return at 0).
  std::size_t separated = 0;
  ErrorStats fcl_distance;  // m
  std::size_t fcl_distance_failures = 0;
  FclCollideStats mpr;  // GST_LIBCCD: libccd MPR penetration
  FclCollideStats epa;  // GST_INDEP: FCL's own GJK/EPA
};

struct ContactValidation {
  std::size_t pairs = 0;
  std::uint64_t seed = 0;
  std::vector<FamilyValidation> families;  // in PairFamily order
  FamilyValidation all;                    // every pair together
};

// Runs `pairs` pairs, spread round-robin over the families. Deterministic for a given seed.
ContactValidation run_contact_validation(std::size_t pairs, std::uint64_t seed);
std::string format_contact_validation(const ContactValidation& v);
// run + format: the human-readable table (per family: max / p99 / median errors vs the reference
// and vs FCL, and FCL failure counts).
std::string contact_validation_report(std::size_t pairs, std::uint64_t seed);

}  // namespace throng::geom
