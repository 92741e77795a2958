#include "display/gl_presenter.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "display/levels_view.h"

namespace frameless {
namespace {

#include "display/gl_presenter_font.inc"

constexpr int kGlyphW = 8, kGlyphH = 16, kGlyphs = 95;

// Full-screen triangle from gl_VertexID: no vertex buffer needed.
const char* kImageVs = R"(#version 330 core
out vec2 uv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  uv = vec2(p.x, 1.0 - p.y);  // image row 0 is the top row
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// mode: 0 shaded, 1 age, 2 count, 3 variance, 4 epoch, 5 levels (see ViewMode); levels are
// coloured on the CPU (levels_color, which the tests check) and uploaded as the image.
const char* kImageFs = R"(#version 330 core
in vec2 uv;
out vec4 color;
uniform sampler2D rgb_tex;
uniform sampler2D layer_tex;
uniform int mode;
uniform int srgb;
vec3 heat(float t) {  // black -> purple -> red -> orange -> pale yellow
  t = clamp(t, 0.0, 1.0);
  vec3 c0 = vec3(0.0), c1 = vec3(0.3, 0.0, 0.5), c2 = vec3(0.85, 0.1, 0.15),
       c3 = vec3(1.0, 0.6, 0.0), c4 = vec3(1.0, 1.0, 0.75);
  if (t < 0.25) return mix(c0, c1, t * 4.0);
  if (t < 0.5) return mix(c1, c2, t * 4.0 - 1.0);
  if (t < 0.75) return mix(c2, c3, t * 4.0 - 2.0);
  return mix(c3, c4, t * 4.0 - 3.0);
}
vec3 encode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() {
  vec3 c = texture(rgb_tex, uv).rgb;
  float v = texture(layer_tex, uv).r;
  if (mode == 1 || mode == 2 || mode == 3) {
    c = heat(v);
  } else if (mode == 4) {
    // v = epochs behind the newest camera (0: current, <0: never sampled).
    float lum = 0.25 + 0.75 * clamp(dot(c, vec3(0.2126, 0.7152, 0.0722)), 0.0, 1.0);
    c = v < 0.0 ? vec3(0.05, 0.05, 0.2)
                : (v == 0.0 ? vec3(0.2, 1.0, 0.3) * lum : vec3(1.0, 0.25, 0.2) * lum / (1.0 + 0.3 * v));
  }
  color = vec4(srgb != 0 ? encode(c) : c, 1.0);
}
)";

const char* kTextVs = R"(#version 330 core
layout(location = 0) in vec4 vert;  // pixel x, y (top-left origin), glyph atlas u, v
uniform vec2 viewport;
out vec2 uv;
void main() {
  uv = vert.zw;
  gl_Position = vec4(vert.x / viewport.x * 2.0 - 1.0, 1.0 - vert.y / viewport.y * 2.0, 0.0, 1.0);
}
)";

// u < 0 marks the panel behind the text.
const char* kTextFs = R"(#version 330 core
in vec2 uv;
out vec4 color;
uniform sampler2D font_tex;
void main() {
  if (uv.x < 0.0) { color = vec4(0.0, 0.0, 0.0, 0.6); return; }
  float a = texture(font_tex, uv).r;
  color = vec4(1.0, 1.0, 0.85, a);
}
)";

}  // namespace

// GL entry points fetched through the context's loader (libGL is never linked directly, so a
// window and an OSMesa context can live in one program).
#define FRAMELESS_GL_FUNCTIONS(X)                                                               \
  X(PFNGLGETSTRINGPROC, GetString) X(PFNGLGETERRORPROC, GetError)                              \
  X(PFNGLVIEWPORTPROC, Viewport) X(PFNGLCLEARCOLORPROC, ClearColor) X(PFNGLCLEARPROC, Clear)    \
  X(PFNGLENABLEPROC, Enable) X(PFNGLDISABLEPROC, Disable) X(PFNGLBLENDFUNCPROC, BlendFunc)      \
  X(PFNGLGENTEXTURESPROC, GenTextures) X(PFNGLDELETETEXTURESPROC, DeleteTextures)               \
  X(PFNGLBINDTEXTUREPROC, BindTexture) X(PFNGLTEXPARAMETERIPROC, TexParameteri)                 \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D) X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                  \
  X(PFNGLPIXELSTOREIPROC, PixelStorei) X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                 \
  X(PFNGLCREATESHADERPROC, CreateShader) X(PFNGLSHADERSOURCEPROC, ShaderSource)                 \
  X(PFNGLCOMPILESHADERPROC, CompileShader) X(PFNGLGETSHADERIVPROC, GetShaderiv)                 \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) X(PFNGLCREATEPROGRAMPROC, CreateProgram)       \
  X(PFNGLATTACHSHADERPROC, AttachShader) X(PFNGLLINKPROGRAMPROC, LinkProgram)                   \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv) X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)       \
  X(PFNGLDELETESHADERPROC, DeleteShader) X(PFNGLDELETEPROGRAMPROC, DeleteProgram)               \
  X(PFNGLUSEPROGRAMPROC, UseProgram) X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)         \
  X(PFNGLUNIFORM1IPROC, Uniform1i) X(PFNGLUNIFORM2FPROC, Uniform2f)                             \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)     \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) X(PFNGLGENBUFFERSPROC, GenBuffers)         \
  X(PFNGLBINDBUFFERPROC, BindBuffer) X(PFNGLBUFFERDATAPROC, BufferData)                         \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers) X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer) \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                  \
  X(PFNGLDRAWARRAYSPROC, DrawArrays) X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)               \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                  \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                                        \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                    \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers) X(PFNGLREADPIXELSPROC, ReadPixels)         \
  X(PFNGLREADBUFFERPROC, ReadBuffer) X(PFNGLFINISHPROC, Finish)

struct GlPresenter::Gl {
#define X(type, name) type name = nullptr;
  FRAMELESS_GL_FUNCTIONS(X)
#undef X
};

const char* to_string(ViewMode mode) {
  switch (mode) {
    case ViewMode::shaded: return "shaded";
    case ViewMode::age: return "age";
    case ViewMode::count: return "count";
    case ViewMode::variance: return "variance";
    case ViewMode::epoch: return "epoch";
    case ViewMode::levels: return "levels";
  }
  return "?";
}

ViewMode next_view(ViewMode mode) { return ViewMode((int(mode) + 1) % kViewModeCount); }

bool parse_view(const std::string& name, ViewMode& mode) {
  for (int m = 0; m < kViewModeCount; ++m)
    if (name == to_string(ViewMode(m))) {
      mode = ViewMode(m);
      return true;
    }
  return false;
}

namespace {

unsigned compile(const GlPresenter::Gl& gl, const char* vs, const char* fs, std::string& error) {
  auto stage = [&](GLenum kind, const char* src) -> GLuint {
    const GLuint s = gl.CreateShader(kind);
    gl.ShaderSource(s, 1, &src, nullptr);
    gl.CompileShader(s);
    GLint ok = 0;
    gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[1024] = {};
      gl.GetShaderInfoLog(s, sizeof log, nullptr, log);
      error = std::string("shader compile failed: ") + log;
      gl.DeleteShader(s);
      return 0;
    }
    return s;
  };
  const GLuint v = stage(GL_VERTEX_SHADER, vs);
  if (!v) return 0;
  const GLuint f = stage(GL_FRAGMENT_SHADER, fs);
  if (!f) {
    gl.DeleteShader(v);
    return 0;
  }
  const GLuint p = gl.CreateProgram();
  gl.AttachShader(p, v);
  gl.AttachShader(p, f);
  gl.LinkProgram(p);
  gl.DeleteShader(v);
  gl.DeleteShader(f);
  GLint ok = 0;
  gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    gl.GetProgramInfoLog(p, sizeof log, nullptr, log);
    error = std::string("shader link failed: ") + log;
    gl.DeleteProgram(p);
    return 0;
  }
  return p;
}

void set_nearest(const GlPresenter::Gl& gl) {
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

Result<std::unique_ptr<GlPresenter>> GlPresenter::create(ProcLoader loader) {
  std::unique_ptr<GlPresenter> p(new GlPresenter());
  std::string error;
  if (!p->init(loader, error)) return Error{"OpenGL: " + error};
  return p;
}

bool GlPresenter::init(ProcLoader loader, std::string& error) {
  gl_ = std::make_unique<Gl>();
  Gl& gl = *gl_;
#define X(type, name)                                                  \
  gl.name = reinterpret_cast<type>(loader("gl" #name));                \
  if (!gl.name) {                                                      \
    error = "missing entry point gl" #name " (need OpenGL 3.3)";       \
    return false;                                                      \
  }
  FRAMELESS_GL_FUNCTIONS(X)
#undef X
  image_program_ = compile(gl, kImageVs, kImageFs, error);
  if (!image_program_) return false;
  text_program_ = compile(gl, kTextVs, kTextFs, error);
  if (!text_program_) return false;
  gl.GenVertexArrays(1, &vao_);
  gl.GenBuffers(1, &text_vbo_);
  GLuint tex[3];
  gl.GenTextures(3, tex);
  rgb_tex_ = tex[0], layer_tex_ = tex[1], font_tex_ = tex[2];
  // Font atlas: the 95 glyphs side by side, one byte per pixel.
  std::vector<unsigned char> atlas(size_t(kGlyphW * kGlyphs * kGlyphH), 0);
  for (int g = 0; g < kGlyphs; ++g)
    for (int y = 0; y < kGlyphH; ++y)
      for (int x = 0; x < kGlyphW; ++x)
        if (kOverlayFont[g][y] & (0x80 >> x))
          atlas[size_t(y * kGlyphW * kGlyphs + g * kGlyphW + x)] = 255;
  gl.BindTexture(GL_TEXTURE_2D, font_tex_);
  set_nearest(gl);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R8, kGlyphW * kGlyphs, kGlyphH, 0, GL_RED, GL_UNSIGNED_BYTE,
                atlas.data());
  gl.UseProgram(image_program_);
  gl.Uniform1i(gl.GetUniformLocation(image_program_, "rgb_tex"), 0);
  gl.Uniform1i(gl.GetUniformLocation(image_program_, "layer_tex"), 1);
  gl.UseProgram(text_program_);
  gl.Uniform1i(gl.GetUniformLocation(text_program_, "font_tex"), 2);
  gl.UseProgram(0);
  if (const GLenum e = gl.GetError(); e != GL_NO_ERROR) {
    error = "GL error " + std::to_string(e) + " during setup";
    return false;
  }
  return true;
}

GlPresenter::~GlPresenter() {
  if (!gl_ || !gl_->DeleteProgram) return;
  Gl& gl = *gl_;
  if (image_program_) gl.DeleteProgram(image_program_);
  if (text_program_) gl.DeleteProgram(text_program_);
  const GLuint tex[4] = {rgb_tex_, layer_tex_, font_tex_, fbo_tex_};
  gl.DeleteTextures(4, tex);
  if (fbo_) gl.DeleteFramebuffers(1, &fbo_);
  if (vao_) gl.DeleteVertexArrays(1, &vao_);
  if (text_vbo_) gl.DeleteBuffers(1, &text_vbo_);
}

ViewScale GlPresenter::upload(const DisplayImage& image, ViewMode mode) {
  Gl& gl = *gl_;
  const size_t n = image.pixels();
  const bool resized = image.width != width_ || image.height != height_;
  width_ = image.width, height_ = image.height;
  mode_ = mode;
  if (n == 0) return scale_;
  // Scales and the false-colour layer: per-pixel work on the GL thread, never on a render thread.
  // Coverage (every view's overlay) in one pass over the epochs: the newest and how many show it.
  ViewScale s;
  uint32_t newest = image.info.newest_epoch;
  size_t current = 0;
  for (size_t i = 0; i < n && i < image.epoch.size(); ++i) {
    const uint32_t ep = image.epoch[i];
    if (ep > newest) newest = ep, current = 0;
    current += ep != 0 && ep == newest;
  }
  // The shaded view (the default) reads the colour alone: the other layers, the scales and the
  // layer texture are left for the views that show them (at 1280x720 they cost the GL thread
  // several milliseconds an image).
  const bool scaled = mode != ViewMode::shaded;
  const bool layered = scaled && mode != ViewMode::levels;  // levels colours the image itself
  if (layered) layer_.assign(n, 0.0f);
  for (size_t i = 0; scaled && i < n; ++i) {
    const float age = i < image.last_update.size() && image.last_update[i] >= 0.0f
                          ? float(image.info.virtual_time) - image.last_update[i]
                          : -1.0f;
    const float count = i < image.sample_count.size() ? float(image.sample_count[i]) : 0.0f;
    const float var = i < image.variance.size() ? image.variance[i] : 0.0f;
    const uint32_t ep = i < image.epoch.size() ? image.epoch[i] : 0;
    const int lv = i < image.levels.size() ? int(image.levels[i]) : 0;
    s.max_levels = std::max(s.max_levels, lv);
    s.max_age = std::max(s.max_age, age);
    s.max_count = std::max(s.max_count, count);
    s.max_variance = std::max(s.max_variance, var);
    switch (mode) {
      case ViewMode::shaded: break;
      case ViewMode::age: layer_[i] = age < 0.0f ? 1.0f : age; break;
      case ViewMode::count: layer_[i] = count; break;
      case ViewMode::variance: layer_[i] = var; break;
      case ViewMode::epoch: layer_[i] = ep == 0 ? -1.0f : float(newest - ep); break;
      case ViewMode::levels: break;
    }
  }
  // The levels view replaces the image itself: the shader shows it as it shows shaded pixels.
  const float* rgb = image.rgb.data();
  if (mode == ViewMode::levels) {
    view_rgb_.resize(3 * n);
    for (size_t i = 0; i < n; ++i) {
      const Vec3 c = levels_color(i < image.levels.size() ? image.levels[i] : 0u);
      view_rgb_[3 * i] = c.x, view_rgb_[3 * i + 1] = c.y, view_rgb_[3 * i + 2] = c.z;
    }
    rgb = view_rgb_.data();
  }
  s.coverage = double(current) / double(n);
  // Normalise the heat maps to [0, 1]: age linear, count and variance on a log scale.
  if (mode == ViewMode::age && s.max_age > 0.0f)
    for (float& v : layer_) v = std::min(v / s.max_age, 1.0f);
  if (mode == ViewMode::count || mode == ViewMode::variance) {
    const float top = std::log1p(mode == ViewMode::count ? s.max_count : s.max_variance * 1e4f);
    const float k = mode == ViewMode::count ? 1.0f : 1e4f;
    for (float& v : layer_) v = top > 0.0f ? std::log1p(v * k) / top : 0.0f;
  }
  scale_ = s;
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, rgb_tex_);
  if (resized) {
    set_nearest(gl);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, width_, height_, 0, GL_RGB, GL_FLOAT, rgb);
  } else {
    gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGB, GL_FLOAT, rgb);
  }
  if (layered) {
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_2D, layer_tex_);
    if (layer_width_ != width_ || layer_height_ != height_) {
      set_nearest(gl);
      gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width_, height_, 0, GL_RED, GL_FLOAT, layer_.data());
      layer_width_ = width_, layer_height_ = height_;
    } else {
      gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RED, GL_FLOAT, layer_.data());
    }
    gl.ActiveTexture(GL_TEXTURE0);
  }
  return s;
}

void GlPresenter::draw(int fb_width, int fb_height, bool srgb) {
  Gl& gl = *gl_;
  gl.Viewport(0, 0, fb_width, fb_height);
  gl.Disable(GL_BLEND);
  gl.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT);
  if (width_ <= 0 || height_ <= 0) return;
  gl.UseProgram(image_program_);
  gl.Uniform1i(gl.GetUniformLocation(image_program_, "mode"), int(mode_));
  gl.Uniform1i(gl.GetUniformLocation(image_program_, "srgb"), srgb ? 1 : 0);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.BindTexture(GL_TEXTURE_2D, rgb_tex_);
  gl.ActiveTexture(GL_TEXTURE1);
  gl.BindTexture(GL_TEXTURE_2D, layer_tex_);
  gl.BindVertexArray(vao_);
  gl.DrawArrays(GL_TRIANGLES, 0, 3);
  gl.BindVertexArray(0);
  gl.ActiveTexture(GL_TEXTURE0);
}

void GlPresenter::draw_text(const std::vector<std::string>& lines, int fb_width, int fb_height,
                            int scale) {
  if (lines.empty()) return;
  Gl& gl = *gl_;
  scale = std::max(scale, 1);
  const float gw = float(kGlyphW * scale), gh = float(kGlyphH * scale), pad = float(4 * scale);
  size_t longest = 0;
  for (const std::string& l : lines) longest = std::max(longest, l.size());
  text_verts_.clear();
  auto quad = [&](float x0, float y0, float x1, float y1, float u0, float v0, float u1, float v1) {
    const float q[6][4] = {{x0, y0, u0, v0}, {x1, y0, u1, v0}, {x1, y1, u1, v1},
                           {x0, y0, u0, v0}, {x1, y1, u1, v1}, {x0, y1, u0, v1}};
    for (const auto& v : q) text_verts_.insert(text_verts_.end(), v, v + 4);
  };
  quad(0, 0, 2 * pad + gw * float(longest), 2 * pad + gh * float(lines.size()), -1, -1, -1, -1);
  for (size_t r = 0; r < lines.size(); ++r)
    for (size_t c = 0; c < lines[r].size(); ++c) {
      const int ch = (unsigned char)lines[r][c];
      if (ch <= 32 || ch > 126) continue;
      const float x = pad + gw * float(c), y = pad + gh * float(r);
      const float u0 = float(ch - 32) / kGlyphs, u1 = float(ch - 31) / kGlyphs;
      quad(x, y, x + gw, y + gh, u0, 0.0f, u1, 1.0f);
    }
  gl.Viewport(0, 0, fb_width, fb_height);
  gl.Enable(GL_BLEND);
  gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  gl.UseProgram(text_program_);
  gl.Uniform2f(gl.GetUniformLocation(text_program_, "viewport"), float(fb_width), float(fb_height));
  gl.ActiveTexture(GL_TEXTURE2);
  gl.BindTexture(GL_TEXTURE_2D, font_tex_);
  gl.BindVertexArray(vao_);
  gl.BindBuffer(GL_ARRAY_BUFFER, text_vbo_);
  gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(text_verts_.size() * sizeof(float)), text_verts_.data(),
                GL_STREAM_DRAW);
  gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  gl.EnableVertexAttribArray(0);
  gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(text_verts_.size() / 4));
  gl.BindBuffer(GL_ARRAY_BUFFER, 0);
  gl.BindVertexArray(0);
  gl.ActiveTexture(GL_TEXTURE0);
  gl.Disable(GL_BLEND);
}

Result<bool> GlPresenter::render_linear(std::vector<float>& rgb) {
  Gl& gl = *gl_;
  if (width_ <= 0 || height_ <= 0) return Error{"OpenGL: nothing uploaded to render"};
  if (!fbo_ || fbo_width_ != width_ || fbo_height_ != height_) {
    if (!fbo_) gl.GenFramebuffers(1, &fbo_);
    if (!fbo_tex_) gl.GenTextures(1, &fbo_tex_);
    gl.BindTexture(GL_TEXTURE_2D, fbo_tex_);
    set_nearest(gl);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, width_, height_, 0, GL_RGBA, GL_FLOAT, nullptr);
    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fbo_tex_, 0);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
      return Error{"OpenGL: float framebuffer (RGBA32F) is not supported by this context"};
    }
    fbo_width_ = width_, fbo_height_ = height_;
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  draw(width_, height_, false);
  std::vector<float> rgba(size_t(width_) * height_ * 4);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.data());
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (const GLenum e = gl.GetError(); e != GL_NO_ERROR)
    return Error{"OpenGL: error " + std::to_string(e) + " while reading back the image"};
  // GL rows run bottom-up; the image's row 0 is the top.
  rgb.resize(size_t(width_) * height_ * 3);
  for (int y = 0; y < height_; ++y) {
    const float* src = rgba.data() + size_t(height_ - 1 - y) * width_ * 4;
    float* dst = rgb.data() + size_t(y) * width_ * 3;
    for (int x = 0; x < width_; ++x)
      for (int c = 0; c < 3; ++c) dst[x * 3 + c] = src[x * 4 + c];
  }
  return true;
}

void GlPresenter::read_rgb8(int width, int height, std::vector<unsigned char>& rgb8) {
  Gl& gl = *gl_;
  std::vector<unsigned char> rgba(size_t(width) * height * 4);
  gl.Finish();
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  rgb8.resize(size_t(width) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        rgb8[(size_t(y) * width + x) * 3 + c] = rgba[(size_t(height - 1 - y) * width + x) * 4 + c];
}

std::string GlPresenter::renderer() const {
  auto str = [&](GLenum e) {
    const GLubyte* s = gl_->GetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return str(GL_RENDERER) + " / OpenGL " + str(GL_VERSION);
}

}  // namespace frameless
