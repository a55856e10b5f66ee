// pbrt_reader.h: a pbrt-v4 scene subset (https://pbrt.org/fileformat-v4) → ltm Scene.
//
// Read: Include/Import; AttributeBegin/End (TransformBegin/End); Identity, Translate, Scale,
// Rotate, LookAt, Transform, ConcatTransform, CoordinateSystem, CoordSysTransform,
// ReverseOrientation; WorldBegin; Camera "perspective" (fov = the shorter image axis) + Film
// x/yresolution; Shape trianglemesh, plymesh (.ply, .ply.gz), bilinearmesh, sphere, disk
// (tessellated); ObjectBegin/End/ObjectInstance; Texture "spectrum" "imagemap"; Material,
// MakeNamedMaterial, NamedMaterial: diffuse (rgb or imagemap reflectance), coateddiffuse and
// diffusetransmission (→ diffuse, warning), conductor (→ GGX conductor; roughness remapped as
// pbrt does; F0 from "reflectance", rgb eta/k, or a table of pbrt's named metals);
// AreaLightSource "diffuse" (L rgb or blackbody, scale). Shapes with dielectric, thindielectric,
// interface and other materials are dropped with a warning naming them (glass passes light, an
// opaque stand-in would be wrong). Renderer settings (Sampler, Integrator, PixelFilter, ...) are
// ignored; LightSource (point, spot, infinite, distant, ...) is out of scope: warned, and a
// scene with no area light is an error saying so.
//
// Conventions: pbrt is left-handed; ltm's camera is right-handed (right = forward × up), so the
// world is mirrored in x (windings flipped, orientation kept) whenever the pbrt camera would
// otherwise come out mirrored. If the camera's up vector is mostly ±x or ±z, the world is turned
// so that it becomes +y (the model was trained with y up). Both are recorded in
// scene.metadata ("pbrt": mirrored_x, up_axis). pbrt has no unit of length: positions are kept.
#pragma once

#include <string>

#include "ltm/scene/scene.h"

namespace ltm {

/// Reads a .pbrt file (and what it includes). Errors: "file:line:col: problem" (ltm::Error).
/// Warnings (ignored or approximated features) go to the log, one line each with a count.
Scene load_pbrt(const std::string &path);

/// The same from text in memory; relative file names resolve against `base_dir`. With
/// allow_files false, any directive that names a file (Include, plymesh, imagemap) is an error
/// (the fuzzer's mode: no input may make the reader open arbitrary paths).
Scene parse_pbrt(const std::string &text, const std::string &file, const std::string &base_dir, bool allow_files = true);

}  // namespace ltm
