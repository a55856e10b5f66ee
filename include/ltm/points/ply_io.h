// ply_io.h: PLY point clouds. Writes binary little-endian with standard names (x y z nx ny nz,
// uchar red green blue for viewers) plus float extras; reads binary little-endian and ASCII.
#pragma once

#include <ostream>
#include <string>

#include "ltm/points/point_set.h"

namespace ltm {

struct PlyWriteOptions {
    bool binary = true;              ///< false: ASCII (for debugging and tests)
    bool add_rgb_from_albedo = true; ///< add uchar red/green/blue (sRGB of albedo_*) for viewers
    std::string comment;             ///< one line written as "comment ..."
};

/// Writes atomically. Column "red"/"green"/"blue" in `points` are written as uchar.
void write_ply(const std::string &path, const PointSet &points, const PlyWriteOptions &opt = {});
/// Writes to a stream (for callers that commit several files together).
void write_ply(std::ostream &out, const PointSet &points, const PlyWriteOptions &opt = {});

/// Reads the "vertex" element (it must come first; later elements are ignored) of a binary
/// little-endian or ASCII PLY. Every scalar property becomes a float column (uchar colours keep
/// their 0–255 values). Errors name the file and, for the header and ASCII data, the line.
PointSet read_ply(const std::string &path);
/// Same, from bytes in memory (used by the fuzzer); `where` names the source in errors.
PointSet parse_ply(const std::string &bytes, const std::string &where);

}  // namespace ltm
