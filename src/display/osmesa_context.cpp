#include "display/osmesa_context.h"

#include <GL/osmesa.h>

namespace frameless {

Result<std::unique_ptr<OsMesaContext>> OsMesaContext::create(int width, int height) {
  if (width <= 0 || height <= 0) return Error{"OSMesa: invalid framebuffer size"};
  std::unique_ptr<OsMesaContext> c(new OsMesaContext());
  const int core[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                      OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                      OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(core, nullptr);
  // Older OSMesa builds only offer the compatibility profile.
  if (!ctx) ctx = OSMesaCreateContextExt(OSMESA_RGBA, 0, 0, 0, nullptr);
  if (!ctx) return Error{"OSMesa: cannot create an OpenGL context"};
  c->context_ = ctx;
  if (!c->resize(width, height)) return Error{"OSMesa: cannot make the context current"};
  return c;
}

OsMesaContext::~OsMesaContext() {
  if (context_) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

bool OsMesaContext::make_current() {
  return OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), buffer_.data(), GL_UNSIGNED_BYTE,
                           width_, height_) == GL_TRUE;
}

bool OsMesaContext::resize(int width, int height) {
  if (width <= 0 || height <= 0) return false;
  buffer_.assign(size_t(width) * size_t(height) * 4, 0);
  width_ = width, height_ = height;
  return make_current();
}

void* OsMesaContext::proc_address(const char* name) {
  return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

}  // namespace frameless
