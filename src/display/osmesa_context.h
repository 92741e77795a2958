// Headless OpenGL context (OSMesa, software) for captures and tests; owned and used by one thread.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/base/error.h"

namespace frameless {

class OsMesaContext {
 public:
  // Creates an OpenGL 3.3 core context (falling back to compatibility) with an RGBA8 default
  // framebuffer of width x height, and makes it current on the calling thread.
  static Result<std::unique_ptr<OsMesaContext>> create(int width, int height);
  ~OsMesaContext();
  OsMesaContext(const OsMesaContext&) = delete;
  OsMesaContext& operator=(const OsMesaContext&) = delete;

  // Makes the context current on the calling thread (with its default framebuffer).
  bool make_current();
  // Reallocates the default framebuffer.
  bool resize(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  // GL entry-point loader for GlPresenter::create.
  static void* proc_address(const char* name);

 private:
  OsMesaContext() = default;
  void* context_ = nullptr;  // OSMesaContext
  std::vector<unsigned char> buffer_;
  int width_ = 0, height_ = 0;
};

}  // namespace frameless
