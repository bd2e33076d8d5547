// The fit advice's rules (see fit_advice.h).
#include "fit/fit_advice.h"

#include <fmt/format.h>

#include <cmath>

namespace lorgnette::fit {

// The difference is judged at the 0.1 mm the advice prints: sizes read from a mesh carry float
// rounding (an 18 mm bridge is 18.0000019 mm), and a difference that reads as the band's edge is on it,
// so no verdict says "too wide by 0.0 mm".
AdviceRule judge(const std::string& name, double difference, double low, double high,
                 const std::string& small, const std::string& large) {
  AdviceRule r;
  r.name = name;
  r.difference_mm = difference;
  r.low_mm = low;
  r.high_mm = high;
  const double d = std::round(difference * 10.0) / 10.0;
  r.verdict = d < low ? small : d > high ? large : "good";
  r.off_by_mm = d < low ? low - difference : d > high ? difference - high : 0.0;
  return r;
}

AdviceRule not_judged(const std::string& name, const std::string& why) {
  AdviceRule r;
  r.name = name;
  r.verdict = "not judged";
  r.text = fmt::format("{}: not judged ({})", name, why);
  return r;
}

namespace {

std::string outcome(const AdviceRule& r) {
  return r.good() ? "good" : fmt::format("{} by {:.1f} mm", r.verdict, r.off_by_mm);
}

}  // namespace

AdviceRule frame_width_rule(double frame, double temples) {
  AdviceRule r = judge("frame_width", frame - temples, -5.0, 5.0, "too narrow", "too wide");
  r.frame_mm = frame, r.head_mm = temples;
  r.text = fmt::format("frame width {:.1f} mm against the face's {:.1f} mm at the temples: {}", frame,
                       temples, outcome(r));
  return r;
}

AdviceRule bridge_rule(double bridge, double nose) {
  AdviceRule r = judge("bridge", bridge - nose, -2.0, 2.0, "too narrow", "too wide");
  r.frame_mm = bridge, r.head_mm = nose;
  r.text = fmt::format("bridge {:.1f} mm against the nose's {:.1f} mm where the pads rest: {}", bridge, nose,
                       outcome(r));
  return r;
}

AdviceRule temple_length_rule(double length, double hinge_to_ear) {
  AdviceRule r = judge("temple_length", length - hinge_to_ear, 25.0, 40.0, "too short", "too long");
  r.frame_mm = length, r.head_mm = hinge_to_ear;
  r.text =
      fmt::format("temples {:.0f} mm against {:.1f} mm from hinge to ear (+25-40 mm to bend behind it): {}",
                  length, hinge_to_ear, outcome(r));
  return r;
}

AdviceRule lens_height_rule(double pupil_above, double lens_height) {
  AdviceRule r = judge("lens_height", pupil_above, -2.0, 6.0, "too high", "too low");
  r.frame_mm = lens_height, r.head_mm = pupil_above;
  r.text = fmt::format("pupils {:+.1f} mm from the centre line of {:.1f} mm tall lenses: {}", pupil_above,
                       lens_height, r.good() ? "good" : fmt::format("the lenses sit {}", outcome(r)));
  return r;
}

FitAdvice fit_advice(const AdviceInputs& in) {
  FitAdvice a;
  a.approximate = in.approximate;
  if (in.frame_width_mm > 0 && in.temple_width_mm > 0)
    a.rules.push_back(frame_width_rule(in.frame_width_mm, in.temple_width_mm));
  else
    a.rules.push_back(not_judged("frame_width", in.why_no_temples.empty()
                                                    ? "the frame's or the face's width is unknown"
                                                    : in.why_no_temples));
  if (!(in.bridge_mm > 0))
    a.rules.push_back(not_judged("bridge", "the frame has no lenses to measure its bridge between"));
  else if (!(in.nose_width_mm > 0))
    a.rules.push_back(
        not_judged("bridge", in.why_no_nose.empty() ? "the nose's width is unknown" : in.why_no_nose));
  else
    a.rules.push_back(bridge_rule(in.bridge_mm, in.nose_width_mm));
  if (in.temple_length_mm > 0 && in.hinge_to_ear_mm > 0)
    a.rules.push_back(temple_length_rule(in.temple_length_mm, in.hinge_to_ear_mm));
  else
    a.rules.push_back(not_judged("temple_length", in.why_no_hinges.empty()
                                                      ? "the frame's temple length is unknown"
                                                      : in.why_no_hinges));
  if (in.lens_height_mm > 0) {
    a.rules.push_back(lens_height_rule(in.pupil_above_centre_mm, in.lens_height_mm));
    if (!in.why_pupils_from_landmarks.empty())
      a.rules.back().text +=
          fmt::format(" (pupils from the eyes' landmarks, which can lie 5 mm off them: {})",
                      in.why_pupils_from_landmarks);
  } else
    a.rules.push_back(not_judged("lens_height", "the frame has no lenses"));
  if (a.approximate)
    for (AdviceRule& r : a.rules)
      if (r.judged()) r.text += " (approximate: the head's size is the mean face's)";
  return a;
}

}  // namespace lorgnette::fit
