// Quick-look outputs of a capture: a PNG contact sheet of evenly spaced frames and, when ffmpeg is
// installed, an MP4 of the whole sequence; run by the capture thread after the frames are written.
#pragma once
#include <string>
#include <vector>

#include "core/base/error.h"

namespace frameless {

struct ContactSheetConfig {
  int max_frames = 16;    // at most this many thumbnails, evenly spaced, first and last included
  int columns = 4;
  int thumb_width = 160;  // thumbnails are box-filtered down to at most this width (never up)
  int gap = 2;            // pixels of dark grey between thumbnails
};

// Reads the EXR frames' R, G, B and writes the grid as an sRGB PNG (temporary name + rename).
Result<bool> write_contact_sheet(const std::vector<std::string>& frame_paths,
                                 const std::string& png_path, const ContactSheetConfig& config = {});

// True when an `ffmpeg` executable is on PATH.
bool ffmpeg_available();
// Encodes the frames (sRGB, H.264, yuv420p) at `fps` into `mp4_path` through ffmpeg
// (temporary name + rename). Error when ffmpeg is missing or fails.
Result<bool> write_mp4(const std::vector<std::string>& frame_paths, double fps,
                       const std::string& mp4_path);

}  // namespace frameless
