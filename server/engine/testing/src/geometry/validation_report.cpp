// Human-readable table of a ContactValidation run (see contact_validation.h).
#include <cstdarg>
#include <cstdio>
#include <string>

#include "throng/geometry/contact_validation.h"

namespace throng::geom {
namespace {

void appendf(std::string& out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void appendf(std::string& out, const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  if (n <= 0) return;
  const auto len = static_cast<std::size_t>(n);
  out.append(buffer, len < sizeof buffer ? len : sizeof buffer - 1);
}

template <typename Row>
void rows(const ContactValidation& v, Row row) {
  for (const FamilyValidation& f : v.families) row(f);
  row(v.all);
}

void collide_section(std::string& out, const ContactValidation& v, const char* title,
                     FclCollideStats FamilyValidation::*member) {
  appendf(out, "\n%s\n", title);
  appendf(out, "%-14s %8s | %9s %9s %9s %9s | %9s %9s %9s | %6s %6s %6s %6s | %6s\n", "family",
          "compared", "depth max", "p99", "median", "|d| p99", "nrm max", "p99", "+-n p99", "sign",
          "depth", "normal", "failed", "no-sep");
  rows(v, [&](const FamilyValidation& f) {
    const FclCollideStats& s = f.*member;
    appendf(out,
            "%-14s %8zu | %9.2e %9.2e %9.2e %9.2e | %9.2e %9.2e %9.2e | %6zu %6zu %6zu %6zu | "
            "%6zu\n",
            f.name.c_str(), s.compared, s.depth_error.max, s.depth_error.p99, s.depth_error.median,
            s.abs_depth_error.p99, s.normal_error.max, s.normal_error.p99, s.axis_error.p99,
            s.wrong_sign, s.bad_depth, s.bad_normal, s.failed_pairs, s.not_separating);
  });
}

}  // namespace

std::string format_contact_validation(const ContactValidation& v) {
  std::string out;
  appendf(out, "Capsule-capsule contact validation: %zu pairs, seed 0x%llx, %zu families\n",
          v.pairs, static_cast<unsigned long long>(v.seed), v.families.size());
  appendf(out, "Absolute errors: distances in m, normals in rad. pen = penetrating pairs.\n");

  appendf(out,
          "\n[1] Closed form (double) vs long-double reference (bound: |err| <= %.0e * "
          "max(1, |coord|))\n",
          kClosedFormRelativeBound);
  appendf(out, "%-14s %6s %6s | %9s %9s %9s | %9s | %9s %9s | %6s %4s\n", "family", "pairs", "pen",
          "dist max", "p99", "median", "max/scale", "nrm max", "p99", ">bound", "bad");
  rows(v, [&](const FamilyValidation& f) {
    appendf(out, "%-14s %6zu %6zu | %9.2e %9.2e %9.2e | %9.2e | %9.2e %9.2e | %6zu %4zu\n",
            f.name.c_str(), f.pairs, f.penetrating, f.closed_distance.max, f.closed_distance.p99,
            f.closed_distance.median, f.closed_max_scaled_error, f.closed_normal.max,
            f.closed_normal.p99, f.closed_bound_violations, f.closed_bad_output);
  });

  appendf(out,
          "\n[2] FCL fcl::distance (GST_LIBCCD, default request) on separated pairs vs "
          "reference (failure: |err| > %.0e m)\n",
          kFclDistanceTolerance);
  appendf(out, "%-14s %9s | %9s %9s %9s | %8s\n", "family", "separated", "dist max", "p99",
          "median", "failures");
  rows(v, [&](const FamilyValidation& f) {
    appendf(out, "%-14s %9zu | %9.2e %9.2e %9.2e | %8zu\n", f.name.c_str(), f.separated,
            f.fcl_distance.max, f.fcl_distance.p99, f.fcl_distance.median, f.fcl_distance_failures);
  });
  appendf(out,
          "Signed fcl::distance is not run: FCL 0.7 routes it through libccd GJK/EPA, which "
          "aborts on an\nassertion (ComputeVisiblePatch) at touching pairs and runs for "
          "seconds to forever on\noverlapping spheres (0.27 s at 1 cm centre distance, > 5 s "
          "at 1 mm, never when coincident).\n");

  appendf(out,
          "\nfcl::collide with contacts. Failures: sign = collision verdict wrong beyond %.0e m "
          "or depth < 0;\ndepth = |depth err| > %.0e m; normal = normal off by > %.0e rad (where "
          "the exact normal is unique).\n|d| = depth error ignoring FCL's sign; +-n = normal "
          "error ignoring its sign; no-sep = moving b by FCL's\ndepth * normal leaves it "
          "penetrating by more than the depth tolerance (not even a valid push-out).\n",
          kVerdictMargin, kFclDepthTolerance, kFclNormalTolerance);
  collide_section(out, v, "[3] FCL collide, GST_LIBCCD (libccd MPR penetration)",
                  &FamilyValidation::mpr);
  collide_section(out, v, "[4] FCL collide, GST_INDEP (FCL GJK/EPA)", &FamilyValidation::epa);
  return out;
}

std::string contact_validation_report(std::size_t pairs, std::uint64_t seed) {
  return format_contact_validation(run_contact_validation(pairs, seed));
}

}  // namespace throng::geom
