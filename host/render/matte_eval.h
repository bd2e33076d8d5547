// How well a model trained on a mask-less capture separates the subject, judged against the true
// mattes of a synthetic room capture (synth --room): per held-out view, the rendered opacity
// (alpha = 1 - T) against the matte, inside the region the model can show at all (pixels whose
// subject point, from the synthetic depth, lies inside the model's box: head to neck; shoulders and
// body below the box are left out of both sides), plus the PSNR of the face (the convex hull of the
// 68 ground-truth landmarks projected into the view), over all of it and over the part the subject
// covers fully.
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/camera_types.h"
#include "host/nerf/model.h"
#include "host/util/image_io.h"

namespace lorgnette::render {

struct MatteView {
  Camera camera{};
  const Image* prediction = nullptr;  // the renderer's RGBA (alpha = opacity)
  const Image* truth = nullptr;       // the photo, RGB(A) linear
  const Image* matte = nullptr;       // 1 channel coverage
  const Image* depth = nullptr;       // 1 channel subject ray distance (+inf off the subject); may be null
  std::vector<Eigen::Vector3f> face_points;  // dataset frame; empty = no face PSNR
};

struct MatteScore {
  double iou = 0.0;   // |pred >= 0.5 and matte >= 0.5| / |either|, in the region
  double leak = 0.0;  // sum of opacity * (1 - matte) / subject pixels, in the region
  // sum of max(0, opacity - matte) / subject pixels, in the region: the opacity a pixel holds beyond
  // the subject's coverage of it. `leak` counts a * (1 - m) as if the opacity were spread over the
  // pixel independently of where the subject lies in it, so a render whose opacity equals the
  // anti-aliased matte (a = m on the outline) scores sum m (1 - m) > 0 there; this one scores 0.
  double leak_excess = 0.0;
  double face_psnr = 0.0;  // sRGB PSNR inside the face hull (0 when no face points)
  // The same over the hull's pixels the subject covers fully (matte >= 0.999): the hull's rim holds
  // room beside the jaw and under the chin, which face_psnr scores as if it were face, so a model
  // that paints the room around the head scores higher there than one that renders it clear.
  double face_psnr_subject = 0.0;
  long subject_pixels = 0, face_pixels = 0, face_subject_pixels = 0;
  // The head's interior left transparent (hole_eval.h), and the worst view's (mean_score: the largest).
  double holes = 0.0, holes_worst = 0.0;
};

MatteScore score_matte(const MatteView& view, const nerf::Aabb& box);

// Whether score_matte judges pixel (x, y) of a view: a room pixel (matte < 0.5) always, a subject pixel
// where its subject point (from `depth`, the ray distance; none or +inf: always) lies inside `box`.
bool judged_pixel(const Camera& camera, const Image& matte, const Image* depth, int x, int y,
                  const nerf::Aabb& box);

// The face fields of `s` (face_psnr, face_psnr_subject and their pixel counts): sRGB PSNR of `pred`
// against `truth` inside the convex hull of `hull_px` (pixel coordinates, rounded; fewer than 3
// points: an empty hull, PSNR 0), and over the hull's pixels `matte` covers fully (>= 0.999).
// score_matte calls it with the projected ground-truth landmarks; a subject without them (a mesh)
// can pass dlib's landmarks on the photo.
void score_face(const Image& pred, const Image& truth, const Image& matte,
                const std::vector<Eigen::Vector2d>& hull_px, MatteScore& s);

// Means over views (face PSNR over views that have a face).
MatteScore mean_score(const std::vector<MatteScore>& scores);

}  // namespace lorgnette::render
