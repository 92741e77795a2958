#include "display/contact_sheet.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "display/atomic_file.h"
#include "display/exr_io.h"
#include "display/png_io.h"

namespace frameless {
namespace {

struct Rgb {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

Result<Rgb> read_rgb(const std::string& path) {
  auto img = read_exr(path);
  if (!img.ok()) return img.error();
  Rgb out;
  out.width = img->width, out.height = img->height;
  const char* names[3] = {"R", "G", "B"};
  out.rgb.assign(size_t(out.width) * out.height * 3, 0.0f);
  for (int c = 0; c < 3; ++c) {
    auto it = img->channels.find(names[c]);
    if (it == img->channels.end()) return Error{path + ": channel " + names[c] + " missing"};
    for (size_t i = 0; i < it->second.size(); ++i) out.rgb[i * 3 + c] = it->second[i];
  }
  return out;
}

// Path of an executable named `name` on PATH, or empty.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream ss(path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    const std::string full = (dir.empty() ? "." : dir) + "/" + name;
    if (access(full.c_str(), X_OK) == 0) return full;
  }
  return {};
}

}  // namespace

Result<bool> write_contact_sheet(const std::vector<std::string>& frames, const std::string& png_path,
                                 const ContactSheetConfig& config) {
  if (frames.empty()) return Error{png_path + ": no frames for a contact sheet"};
  const int n = std::min<int>(int(frames.size()), std::max(config.max_frames, 1));
  std::vector<size_t> pick;
  for (int i = 0; i < n; ++i)
    pick.push_back(n == 1 ? 0 : size_t(i) * (frames.size() - 1) / size_t(n - 1));
  auto first = read_rgb(frames[pick[0]]);
  if (!first.ok()) return first.error();
  const int factor = std::max(1, (first->width + config.thumb_width - 1) / config.thumb_width);
  const int tw = std::max(1, first->width / factor), th = std::max(1, first->height / factor);
  const int cols = std::min(n, std::max(config.columns, 1)), rows = (n + cols - 1) / cols;
  const int W = cols * tw + (cols + 1) * config.gap, H = rows * th + (rows + 1) * config.gap;
  std::vector<float> sheet(size_t(W) * H * 3, 0.1f);
  for (int k = 0; k < n; ++k) {
    auto img = k == 0 ? std::move(first) : read_rgb(frames[pick[size_t(k)]]);
    if (!img.ok()) return img.error();
    const int ox = config.gap + (k % cols) * (tw + config.gap);
    const int oy = config.gap + (k / cols) * (th + config.gap);
    // Box filter: average factor x factor source pixels per thumbnail pixel.
    for (int y = 0; y < th; ++y)
      for (int x = 0; x < tw; ++x) {
        float acc[3] = {0, 0, 0};
        int cnt = 0;
        for (int sy = y * factor; sy < std::min((y + 1) * factor, img->height); ++sy)
          for (int sx = x * factor; sx < std::min((x + 1) * factor, img->width); ++sx, ++cnt)
            for (int c = 0; c < 3; ++c) acc[c] += img->rgb[(size_t(sy) * img->width + sx) * 3 + c];
        for (int c = 0; c < 3; ++c)
          sheet[(size_t(oy + y) * W + ox + x) * 3 + c] = cnt ? acc[c] / float(cnt) : 0.0f;
      }
  }
  return write_png(png_path, W, H, sheet.data());
}

bool ffmpeg_available() { return !find_on_path("ffmpeg").empty(); }

Result<bool> write_mp4(const std::vector<std::string>& frames, double fps, const std::string& mp4_path) {
  const std::string ffmpeg = find_on_path("ffmpeg");
  if (ffmpeg.empty()) return Error{mp4_path + ": ffmpeg is not installed (apt-get install ffmpeg)"};
  if (frames.empty()) return Error{mp4_path + ": no frames to encode"};
  auto first = read_rgb(frames[0]);
  if (!first.ok()) return first.error();
  const int w = first->width, h = first->height;
  const std::string tmp = temporary_path_for(mp4_path) + ".mp4";
  char cmd[4096];
  // Raw sRGB frames on stdin; H.264 needs even sizes, so pad by one pixel where needed (the
  // filter is quoted: its parentheses would be shell syntax).
  std::snprintf(cmd, sizeof cmd,
                "'%s' -y -loglevel error -f rawvideo -pix_fmt rgb24 -s %dx%d -r %.6f -i - "
                "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p -f mp4 '%s'",
                ffmpeg.c_str(), w, h, fps, tmp.c_str());
  std::FILE* pipe = popen(cmd, "w");
  if (!pipe) return Error{mp4_path + ": cannot start ffmpeg"};
  std::vector<unsigned char> rgb8(size_t(w) * h * 3);
  bool ok = true;
  for (size_t i = 0; i < frames.size() && ok; ++i) {
    auto img = i == 0 ? std::move(first) : read_rgb(frames[i]);
    if (!img.ok() || img->width != w || img->height != h) {
      ok = false;
      break;
    }
    for (size_t k = 0; k < rgb8.size(); ++k) rgb8[k] = linear_to_srgb8(img->rgb[k]);
    ok = std::fwrite(rgb8.data(), 1, rgb8.size(), pipe) == rgb8.size();
  }
  const int status = pclose(pipe);
  if (!ok || status != 0) {
    std::remove(tmp.c_str());
    return Error{mp4_path + ": ffmpeg failed to encode the frames"};
  }
  std::string error;
  if (!commit_temporary(tmp, mp4_path, error)) return Error{error};
  return true;
}

}  // namespace frameless
