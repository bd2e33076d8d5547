// Fit advice: whether a frame fits a head, rule by rule, from sizes in millimetres. Each rule compares
// one number of the frame with one of the head and says good / too small / too large, and by how many
// mm. The tolerances are our reading of the optical trade's usual dispensing practice (Brooks &
// Borish, "System for Ophthalmic Dispensing", 3rd ed., 2007, chapters on frame selection and
// adjustment; Jalie, "Ophthalmic Lenses and Dispensing", 3rd ed., 2008), not figures quoted from them:
//   - frame width: the front about as wide as the face at the temples, so the temples run straight
//     back without pressing or standing off: within +-5 mm;
//   - bridge: the bridge (the distance between the lenses) matched to the nose's width where the pads
//     rest: within +-2 mm (narrower: the frame perches high; wider: it slides down the nose);
//   - temple length: from the hinge to the top of the ear plus a bend (the drop) of 25-40 mm behind it;
//   - lens height: the pupil at or a little above the lens' horizontal centre line: from 2 mm below
//     it to 6 mm above it (below: the lens sits too high; above: the lower rim crosses the view).
//     The pupils are the limbus centres; when those were not found, the eyes' landmark means, which
//     can lie 5 mm off the pupil (over half the band), so the rule's text says so.
// A rule whose inputs are missing is "not judged" with the reason. With the mean face's scale every
// head size is approximate, and the advice says so.
#pragma once
#include <string>
#include <vector>

namespace lorgnette::fit {

struct AdviceRule {
  std::string name;     // "frame_width" | "bridge" | "temple_length" | "lens_height"
  std::string verdict;  // "good", a rule's own words ("too narrow", "too long", ...) or "not judged"
  double frame_mm = 0.0, head_mm = 0.0;  // the two numbers compared
  double difference_mm = 0.0;            // what the band judges (frame - head, or the rule's offset)
  double low_mm = 0.0, high_mm = 0.0;    // the good band for difference_mm
  double off_by_mm = 0.0;                // how far outside the band (0 when good)
  std::string text;                      // one line for a person
  bool judged() const { return verdict != "not judged"; }
  bool good() const { return verdict == "good"; }
};

struct FitAdvice {
  bool approximate = false;  // the head's sizes come from the mean face
  std::vector<AdviceRule> rules;
};

// The band's rule: "good" inside [low, high], `small` below, `large` above (off_by_mm: the distance).
AdviceRule judge(const std::string& name, double difference_mm, double low_mm, double high_mm,
                 const std::string& small, const std::string& large);
AdviceRule not_judged(const std::string& name, const std::string& why);

AdviceRule frame_width_rule(double frame_width_mm, double temple_width_mm);
AdviceRule bridge_rule(double bridge_mm, double nose_width_mm);
AdviceRule temple_length_rule(double temple_length_mm, double hinge_to_ear_mm);
// `pupil_above_centre_mm`: the pupils' height above the lens' horizontal centre line (mm, up +).
AdviceRule lens_height_rule(double pupil_above_centre_mm, double lens_height_mm);

// The numbers the rules compare; 0 (or negative) means not measured, with the reason in `why_*`.
struct AdviceInputs {
  double frame_width_mm = 0, temple_width_mm = 0;
  double bridge_mm = 0, nose_width_mm = 0;
  double temple_length_mm = 0, hinge_to_ear_mm = 0;
  double lens_height_mm = 0, pupil_above_centre_mm = 0;
  std::string why_no_nose, why_no_hinges, why_no_temples;
  bool approximate = false;
  // Set when the pupils are the eyes' landmark means, not the limbus centres: why (the rule says so).
  std::string why_pupils_from_landmarks;
};

// Every rule whose inputs are there; the others "not judged" saying why.
FitAdvice fit_advice(const AdviceInputs& in);

}  // namespace lorgnette::fit
