// What the public API's handles hold (include/frameless/api.h): the library's own objects.
#pragma once
#include <memory>
#include <string>

#include "core/base/error.h"
#include "core/scene/scene.h"
#include "frameless/api.h"

namespace frameless::api {

struct Scene::Impl {
  std::shared_ptr<const ::frameless::Scene> scene;
};

// Library cameras and images from and to the API's.
::frameless::Camera to_camera(const Camera& c);
Camera from_camera(const ::frameless::Camera& c);
// Empty when the camera is usable, else what is wrong (one line).
std::string camera_problem(const Camera& c);

// Runs `body`, turning anything it throws into a one-line failure (never an exit or abort).
template <class T, class F>
Result<T> guarded(F&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return Result<T>::failure("out of memory");
  } catch (const std::exception& e) {
    return Result<T>::failure(one_line(e.what()));
  } catch (...) {
    return Result<T>::failure("unknown error");
  }
}

}  // namespace frameless::api
