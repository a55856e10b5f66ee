// gltf_reader.h: glTF 2.0 (.gltf with external or data-URI buffers, .glb) → ltm Scene, through
// Debian's tinygltf. Read: the default scene's node hierarchy (matrix or TRS), triangle
// primitives (strips and fans converted; points and lines skipped with a warning), TEXCOORD_0,
// materials (baseColorFactor × baseColorTexture → albedo; metallicFactor = 1 → GGX conductor with
// F0 = base colour and α = roughness²; emissiveFactor × KHR_materials_emissive_strength →
// emitted radiance), and the first perspective camera. glTF is right-handed, y up, metres and
// counter-clockwise front faces — ltm's own conventions, so nothing is mirrored or turned.
// Sparse accessors and morph targets are refused (one-line error naming the accessor).
#pragma once

#include <string>

#include "ltm/scene/scene.h"

namespace ltm {

/// Reads .gltf or .glb (by extension). Errors name the file ("file: problem"); embedded images
/// become in-memory textures named "<file>#image<i>" (ltm convert writes them out as PNG).
Scene load_gltf(const std::string &path);
/// The same from bytes in memory (binary: a .glb container, else glTF JSON); external URIs are an
/// error (only data URIs and the GLB buffer are read). `where` names the source. Used by the fuzzer.
Scene parse_gltf(const std::string &bytes, const std::string &where, bool binary);

}  // namespace ltm
