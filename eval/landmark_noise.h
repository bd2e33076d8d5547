// Detector noise for stability studies: a landmark detector whose 2D landmarks carry added Gaussian
// noise, so that a benchmark sees how the fit degrades as the detector gets worse. The fit itself
// never adds noise; a study passes this detector as FitOptions::detection.detect.
#pragma once
#include "fit/landmarks_dlib.h"

namespace lorgnette::fit {

// `inner`'s detections with N(0, sigma_px) added to each landmark's x and y, drawn from one generator
// seeded with `seed` in the order of the calls (the fit detects its views one at a time, in order, so a
// run draws the same noise whether or not the detection overlaps the next render). Boxes are unchanged.
DetectFn with_landmark_noise(DetectFn inner, double sigma_px, unsigned seed);

// dlib's detector (landmarks_dlib.h) with that noise.
DetectFn noisy_dlib_detector(const DetectorOptions& options, double sigma_px, unsigned seed);

}  // namespace lorgnette::fit
