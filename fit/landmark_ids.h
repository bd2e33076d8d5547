// Names of the iBUG/dlib 68-point landmarks the fit uses (0-based indices), and which ones are rigid
// enough for aligning a mean face (the jaw contour 0-16 slides with the view, the mouth moves).
#pragma once

namespace lorgnette::fit::lm {

constexpr int kCount = 68;
// Jaw contour ends: the topmost contour points, at the tragus/temple height beside the eyes. They are
// the dlib points nearest to the paper's temple landmarks (FaceMesh 127/356 sit on the same spot).
constexpr int kTempleR = 0;         // subject's right (image left in a frontal view)
constexpr int kTempleL = 16;        // subject's left
constexpr int kNoseBridgeTop = 27;  // between the eyes
constexpr int kNoseBridge2 = 28;
constexpr int kNoseTip = 30;
constexpr int kEyeOuterR = 36;  // subject's right eye, outer corner
constexpr int kEyeInnerR = 39;
constexpr int kEyeInnerL = 42;
constexpr int kEyeOuterL = 45;
constexpr int kEyeRFirst = 36, kEyeRLast = 41;
constexpr int kEyeLFirst = 42, kEyeLLast = 47;
constexpr int kRigidFirst = 17, kRigidLast = 47;  // brows, nose, eyes

}  // namespace lorgnette::fit::lm
