// Neck and shoulders for the procedural head, so a subject filmed in a room does not float: a
// closed lofted surface (superelliptic horizontal cross-sections whose half-widths follow a neck ->
// trapezius -> shoulder -> chest profile) in the head frame (millimetres, eye level at y = 0, face
// towards +z). Its top lies inside the head's own neck cylinder, so the joint is hidden; the neck is
// painted with the head's skin colour and the torso with a striped shirt (texture for the NeRF).
#pragma once
#include "mesh/trimesh.h"
#include "synth/head_params.h"

namespace lorgnette::synth {

// Part name "body"; one material with its own texture (index 0 of the returned mesh).
mesh::TriMesh make_neck_and_shoulders(const HeadParams& params);

// Lowest y (mm, head frame) of the body mesh: views framing the shoulders stay above it.
float body_bottom_mm(const HeadParams& params);

}  // namespace lorgnette::synth
