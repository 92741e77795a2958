// A small application that embeds frameless through its installed API (docs/api.md): its own
// GLFW window and loop, the engine's display image drawn each frame, the camera orbiting with the
// arrow keys (or by itself with --orbit). Built against an installed tree:
//   cmake -S examples/embed -B build/embed -DCMAKE_PREFIX_PATH=PREFIX && cmake --build build/embed
//   build/embed/embed [SCENE] [--frames N] [--orbit]
#include <GLFW/glfw3.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <frameless/api.h>

using namespace frameless::api;

int main(int argc, char** argv) {
  std::string spec = "default";
  long frames = -1;  // run until the window closes
  bool orbit = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atol(argv[++i]);
    else if (!std::strcmp(argv[i], "--orbit")) orbit = true;
    else if (!std::strcmp(argv[i], "--help")) {
      std::printf("usage: embed [SCENE] [--frames N] [--orbit]\n");
      return 0;
    } else spec = argv[i];
  }
  auto scene = Scene::load(spec);
  if (!scene) {
    std::fprintf(stderr, "embed: %s\n", scene.error().c_str());
    return 2;
  }
  if (!glfwInit()) {
    std::fprintf(stderr, "embed: no display (GLFW could not start)\n");
    return 3;
  }
  constexpr int kW = 480, kH = 270;
  GLFWwindow* window = glfwCreateWindow(kW, kH, "frameless embedded", nullptr, nullptr);
  if (!window) {
    std::fprintf(stderr, "embed: no window\n");
    glfwTerminate();
    return 3;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  EngineOptions options;
  options.width = kW;
  options.height = kH;
  auto engine = Engine::start(*scene, options);
  if (!engine) {
    std::fprintf(stderr, "embed: %s\n", engine.error().c_str());
    return 2;
  }
  Camera cam = scene->camera();
  const float dx = cam.eye[0] - cam.look[0], dz = cam.eye[2] - cam.look[2];
  const float radius = std::sqrt(dx * dx + dz * dz);
  float angle = std::atan2(dx, dz);
  std::vector<float> pixels;
  auto next = std::chrono::steady_clock::now();
  for (long frame = 0; !glfwWindowShouldClose(window) && frame != frames; ++frame) {
    next += std::chrono::microseconds(16667);  // 60 frames a second where no vsync paces them
    std::this_thread::sleep_until(next);
    glfwPollEvents();
    float turn = 0.0f;
    if (glfwGetKey(window, GLFW_KEY_LEFT) == GLFW_PRESS) turn -= 0.03f;
    if (glfwGetKey(window, GLFW_KEY_RIGHT) == GLFW_PRESS) turn += 0.03f;
    if (orbit) turn += 0.01f;
    if (turn != 0.0f) {
      angle += turn;
      cam.eye[0] = cam.look[0] + radius * std::sin(angle);
      cam.eye[2] = cam.look[2] + radius * std::cos(angle);
      if (auto r = engine->set_camera(cam); !r) std::fprintf(stderr, "embed: %s\n", r.error().c_str());
    }
    // The display's newest image, tone mapped (clamp, gamma 2.2) and flipped for glDrawPixels.
    const Image img = engine->image();
    pixels.resize(img.data.size());
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width * 3; ++x) {
        const float v = img.data[size_t(img.height - 1 - y) * size_t(img.width) * 3 + size_t(x)];
        pixels[size_t(y) * size_t(img.width) * 3 + size_t(x)] = std::pow(v < 0 ? 0.0f : v > 1 ? 1.0f : v, 1.0f / 2.2f);
      }
    glClear(GL_COLOR_BUFFER_BIT);
    if (img.width == kW && img.height == kH) glDrawPixels(kW, kH, GL_RGB, GL_FLOAT, pixels.data());
    glfwSwapBuffers(window);
  }
  // What the window shows now: its mean brightness, read back (0 would mean nothing was drawn).
  std::vector<float> shown(size_t(kW) * kH * 3);
  glReadPixels(0, 0, kW, kH, GL_RGB, GL_FLOAT, shown.data());
  double mean = 0;
  for (float v : shown) mean += v;
  mean /= double(shown.size());
  const EngineStats s = engine->stats();
  std::printf("embed: %s, %.1f s, %llu samples (%.2f M/s), %llu pixel updates shown, window mean %.3f\n", spec.c_str(),
              s.seconds, (unsigned long long)s.samples, s.samples_per_s * 1e-6, (unsigned long long)s.pixel_updates, mean);
  engine->stop();
  glfwDestroyWindow(window);
  glfwTerminate();
  return s.samples > 0 ? 0 : 1;
}
