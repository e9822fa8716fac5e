#pragma once
// The verdict of a diagnosis, one type for the chair's (sysid/diagnose/) and the axis'
// (sysid/platform/axis_diagnose.h): header-only, so that both libraries include it without
// either linking the other (both depend on engine only).
//
// Both diagnoses choose causes on training and selection data and then read their report data
// once; the verdict states what the report data show:
//   adequate          the base model's residual cannot be told from measurement noise;
//   explained         at least one cause is confirmed (its gain on the report data is positive
//                     beyond its uncertainty) and the extended model's residual is noise-like;
//   partly_explained  at least one confirmed cause, but structure is left;
//   unexplained       the base model is measurably wrong and no cause is confirmed (causes
//                     chosen on the selection data but not confirmed are still reported).
// `cause` is none for adequate and unexplained: "the model is fine" and "the model is wrong and
// the cause is unknown" lead a lab to opposite decisions and must never be confused.

#include <cstddef>

namespace pwsim::diagnose {

enum class Verdict { kAdequate, kExplained, kPartlyExplained, kUnexplained };

/// "adequate", "explained", "partly_explained", "unexplained".
inline const char* VerdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kAdequate: return "adequate";
    case Verdict::kExplained: return "explained";
    case Verdict::kPartlyExplained: return "partly_explained";
    case Verdict::kUnexplained: return "unexplained";
  }
  return "unexplained";
}

/// The rule above on what the report data show.
inline Verdict DecideVerdict(bool base_noise_like, std::size_t confirmed_causes,
                             bool extended_noise_like) {
  if (base_noise_like) return Verdict::kAdequate;
  if (confirmed_causes == 0) return Verdict::kUnexplained;
  return extended_noise_like ? Verdict::kExplained : Verdict::kPartlyExplained;
}

}  // namespace pwsim::diagnose
