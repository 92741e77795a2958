// OpenGL presentation of the display image: texture upload, a full-screen quad that shows one of
// the per-pixel views, and a bitmap-font text overlay. The same code draws into a GLFW window and
// into an OSMesa context; it runs on the thread that owns the current GL context.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "display/display_image.h"

namespace frameless {

// What the image shows: the shaded display image or one per-pixel layer as a false-colour map.
// levels: reflection/refraction levels per pixel (display/levels_view.h).
enum class ViewMode { shaded, age, count, variance, epoch, levels };
inline constexpr int kViewModeCount = 6;
const char* to_string(ViewMode mode);  // "shaded", "age", "count", "variance", "epoch", "levels"
ViewMode next_view(ViewMode mode);
// The mode named `name` (as to_string writes it); false if there is none.
bool parse_view(const std::string& name, ViewMode& mode);

// Scales of the false-colour views, found from the image at upload (shown in the overlay).
struct ViewScale {
  float max_age = 0;       // seconds
  float max_count = 0;     // samples
  float max_variance = 0;  // luminance variance
  int max_levels = 0;      // reflection/refraction levels
  double coverage = 0;     // fraction of pixels on the newest camera epoch
};

class GlPresenter {
 public:
  // Looks up a GL entry point by name in the current context (glfwGetProcAddress, OSMesaGetProcAddress).
  using ProcLoader = void* (*)(const char* name);
  // Needs a current context with OpenGL 3.3 core (or compatible): compiles shaders, makes textures.
  static Result<std::unique_ptr<GlPresenter>> create(ProcLoader loader);
  ~GlPresenter();
  GlPresenter(const GlPresenter&) = delete;
  GlPresenter& operator=(const GlPresenter&) = delete;

  // Uploads the display image and the layer `mode` shows. Row 0 of the image is the top row.
  ViewScale upload(const DisplayImage& image, ViewMode mode);
  // Draws the uploaded image over the viewport (0, 0, fb_width, fb_height) of the bound
  // framebuffer; srgb: encode for a screen (windows), else linear values (float capture targets).
  void draw(int fb_width, int fb_height, bool srgb);
  // Draws text lines from the top-left corner on a translucent panel (scale: pixel size of a font pixel).
  void draw_text(const std::vector<std::string>& lines, int fb_width, int fb_height, int scale = 1);
  // Draws the uploaded image, linear and without overlay, into a float framebuffer of the image's
  // size and reads it back: RGB floats, row 0 at the top. This is what captures write.
  Result<bool> render_linear(std::vector<float>& rgb);
  // Reads the default framebuffer as 8-bit RGB, row 0 at the top (screenshots).
  void read_rgb8(int width, int height, std::vector<unsigned char>& rgb8);
  // GL_RENDERER and GL_VERSION, for logs and the manifest.
  std::string renderer() const;

  struct Gl;

 private:
  GlPresenter() = default;
  bool init(ProcLoader loader, std::string& error);
  std::unique_ptr<Gl> gl_;
  unsigned image_program_ = 0, text_program_ = 0, vao_ = 0, text_vbo_ = 0;
  unsigned rgb_tex_ = 0, layer_tex_ = 0, font_tex_ = 0, fbo_ = 0, fbo_tex_ = 0;
  int width_ = 0, height_ = 0, fbo_width_ = 0, fbo_height_ = 0;
  int layer_width_ = 0, layer_height_ = 0;  // the layer texture's size (uploaded for layered views only)
  ViewMode mode_ = ViewMode::shaded;
  ViewScale scale_;
  std::vector<float> layer_;      // scratch for the false-colour layer (display-side only)
  std::vector<float> view_rgb_;   // scratch for views coloured on the CPU (levels)
  std::vector<float> text_verts_; // scratch for overlay quads
};

}  // namespace frameless
