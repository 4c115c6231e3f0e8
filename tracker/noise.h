#pragma once
// The profile's noise level, taken from the data, and the tracker's
// tolerances scaled with it, so that one set of defaults works from ideal
// profiles to a real sensor's 0.2 mm RMS (docs/JOINTS.md, "Noise").
#include "tracker/params.h"
#include "tracker/types.h"

namespace vts::tracker {

// Robust estimate of the noise across the surface (1 sigma, mm) of one
// profile: each usable point's distance from the chord through the usable
// points two columns before and after it, over runs of five consecutive
// usable columns in the region of interest [roi_first, roi_last] (roi_last < 0:
// to the end). For independent noise sigma across a straight surface that
// distance has a standard deviation of sqrt(1.5) sigma; corners, edges,
// reflections and dropouts touch few such runs, so the median absolute value
// is taken: sigma = median / (0.6745 sqrt(1.5)). Spread over at most
// kNoiseSamples runs. 0 when fewer than 8 runs exist.
inline constexpr int kNoiseSamples = 96;
double estimate_noise_mm(const ProfileView& profile, int roi_first = 0, int roi_last = -1);

// The parameters the tracker runs with on a profile of noise sigma_mm (1
// sigma): every tolerance that noise must not cross is raised to its
// NoiseParams multiple of sigma_mm, never lowered below the value in
// `params` (so ideal profiles run with the defaults). With
// NoiseParams::adapt off, `params` unchanged.
TrackerParams scaled_for_noise(const TrackerParams& params, double sigma_mm);

}  // namespace vts::tracker
