// The Cycles peer: a generated Blender script (geometry, materials, camera, render settings),
// blender run in the background, its EXR read back.
#include "bench/cycles_peer.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "bench/bench_report.h"
#include "core/io/image_io.h"

namespace frameless::bench {
namespace {

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string vec(const Vec3& v) {
  char b[112];
  std::snprintf(b, sizeof b, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
  return b;
}

// The script: geometry as one mesh with per-face materials, Diffuse (+ Emission) shaders, the
// background as the world, and Cycles set up as a plain unbiased path tracer (no clamping, no
// light threshold, no glossy blur, no denoising, no adaptive sampling, box pixel filter).
std::string cycles_script(const Scene& s, int width, int height, int spp, int threads, int seed,
                          const std::string& exr) {
  std::ostringstream py;
  py << "import bpy, math, time\nfrom mathutils import Vector\n"
     << "bpy.ops.wm.read_factory_settings(use_empty=True)\n"
     << "sc = bpy.context.scene\nsc.render.engine = 'CYCLES'\ncy = sc.cycles\ncy.device = 'CPU'\n"
     << "cy.samples = " << spp << "\ncy.use_adaptive_sampling = False\ncy.use_denoising = False\n"
     << "for k in ('max_bounces', 'diffuse_bounces', 'glossy_bounces', 'transmission_bounces', "
        "'transparent_max_bounces'):\n    setattr(cy, k, " << s.settings.max_depth << ")\n"
     << "cy.volume_bounces = 0\ncy.sample_clamp_direct = 0\ncy.sample_clamp_indirect = 0\n"
     << "cy.light_sampling_threshold = 0\ncy.blur_glossy = 0\ncy.seed = " << seed << "\n"
     << "cy.pixel_filter_type = 'BOX'\ncy.filter_width = 1.0\n"
     << "sc.render.threads_mode = 'FIXED'\nsc.render.threads = " << threads << "\n"
     << "sc.render.resolution_x = " << width << "\nsc.render.resolution_y = " << height
     << "\nsc.render.resolution_percentage = 100\n"
     << "sc.render.image_settings.file_format = 'OPEN_EXR'\n"
     << "sc.render.image_settings.color_depth = '32'\nsc.view_settings.view_transform = 'Standard'\n"
     << "w = bpy.data.worlds.new('world')\nsc.world = w\nw.use_nodes = True\n"
     << "w.node_tree.nodes['Background'].inputs[0].default_value = " << "(" << num(s.settings.background.x)
     << ", " << num(s.settings.background.y) << ", " << num(s.settings.background.z) << ", 1)\n"
     << "w.node_tree.nodes['Background'].inputs[1].default_value = 1.0\n"
     << "mats = []\n"
     << "def material(name, kd, e):\n"
     << "    m = bpy.data.materials.new(name)\n    m.use_nodes = True\n    nt = m.node_tree\n"
     << "    nt.nodes.clear()\n    out = nt.nodes.new('ShaderNodeOutputMaterial')\n"
     << "    d = nt.nodes.new('ShaderNodeBsdfDiffuse')\n    d.inputs['Color'].default_value = kd + (1,)\n"
     << "    d.inputs['Roughness'].default_value = 0\n    shader = d.outputs[0]\n"
     << "    if max(e) > 0:\n        em = nt.nodes.new('ShaderNodeEmission')\n"
     << "        em.inputs['Color'].default_value = e + (1,)\n        em.inputs['Strength'].default_value = 1\n"
     << "        add = nt.nodes.new('ShaderNodeAddShader')\n        nt.links.new(shader, add.inputs[0])\n"
     << "        nt.links.new(em.outputs[0], add.inputs[1])\n        shader = add.outputs[0]\n"
     << "    nt.links.new(shader, out.inputs['Surface'])\n    mats.append(m)\n";
  for (const Material& m : s.materials)
    py << "material('" << (m.name.empty() ? "m" : "m_") << "', " << vec(m.kd) << ", " << vec(m.emission) << ")\n";
  const Geometry& g = s.geometry;
  py << "verts = [";
  for (const Vec3& p : g.positions) py << vec(p) << ",";
  py << "]\nfaces = [";
  for (const UVec3& t : g.triangles) py << "(" << t.x << "," << t.y << "," << t.z << "),";
  py << "]\nfmat = [";
  for (uint32_t i = 0; i < g.num_triangles(); ++i) py << g.material_of(i) << ",";
  py << "]\nme = bpy.data.meshes.new('scene')\nme.from_pydata(verts, [], faces)\n"
     << "for m in mats:\n    me.materials.append(m)\n"
     << "for p, k in zip(me.polygons, fmat):\n    p.material_index = k\n    p.use_smooth = False\n"
     << "ob = bpy.data.objects.new('scene', me)\nsc.collection.objects.link(ob)\n";
  const Camera& c = s.camera;
  const double half = std::tan(double(c.fov_deg) * 3.14159265358979323846 / 360.0);
  py << "cd = bpy.data.cameras.new('camera')\ncd.sensor_fit = 'VERTICAL'\ncd.sensor_height = 24\n"
     << "cd.lens = " << num(12.0 / half) << "\ncd.clip_start = 1e-3\ncd.clip_end = 1e7\n"
     << "co = bpy.data.objects.new('camera', cd)\nsc.collection.objects.link(co)\nsc.camera = co\n"
     << "co.location = " << vec(c.eye) << "\n"
     << "co.rotation_mode = 'QUATERNION'\n"
     << "co.rotation_quaternion = (Vector(" << vec(c.look) << ") - Vector(" << vec(c.eye)
     << ")).to_track_quat('-Z', 'Y')\n"
     << "t0 = time.time()\nbpy.ops.render.render()\nt = time.time() - t0\n"
     << "bpy.data.images['Render Result'].save_render('" << exr << "')\n"
     << "print('FRAMELESS_CYCLES', t, bpy.app.version_string)\n";
  return py.str();
}

}  // namespace

std::string find_blender() {
  const char* path = std::getenv("PATH");
  std::string p = path ? path : "";
  size_t start = 0;
  while (start <= p.size()) {
    const size_t end = p.find(':', start);
    const std::string dir = p.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const std::string f = (dir.empty() ? "." : dir) + "/blender";
    struct stat st;
    if (stat(f.c_str(), &st) == 0 && S_ISREG(st.st_mode) && (st.st_mode & S_IXUSR)) return f;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return "";
}

std::string cycles_unsupported(const Scene& s) {
  if (!s.lights.empty()) return "Parker's lights have no Cycles counterpart";
  if (s.ambient.kind != AmbientKind::kNone) return "the ambient term has no Cycles counterpart";
  if (s.environment) return "environment maps are not exported";
  if (s.geometry.num_spheres() + s.geometry.num_patches() > 0 || !s.geometry.instances.empty() ||
      !s.dynamic.empty())
    return "only plain triangles are exported";
  for (const Material& m : s.materials)
    if (m.cls != MaterialClass::kDiffuse || m.textured())
      return "material '" + m.name + "' is not an untextured diffuse one";
  return "";
}

Result<CyclesRender> render_with_cycles(const std::string& blender, const Scene& scene, int width,
                                        int height, int spp, int threads, int seed,
                                        const std::string& work_dir) {
  const std::string why = cycles_unsupported(scene);
  if (!why.empty()) return Error{"Cycles peer: " + why};
  const std::string script = work_dir + "/cycles_scene.py";
  const std::string exr = work_dir + "/cycles_" + std::to_string(spp) + "spp.exr";
  {
    std::FILE* f = std::fopen(script.c_str(), "w");
    if (!f) return Error{script + ": cannot write the Blender script"};
    const std::string text = cycles_script(scene, width, height, spp, threads, seed, exr);
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    if (std::fclose(f) != 0 || !ok) return Error{script + ": cannot write the Blender script"};
  }
  std::remove(exr.c_str());
  const std::string cmd = "'" + blender + "' -b --factory-startup -noaudio --python-exit-code 1 -P '" + script + "'";
  std::string output;
  const int status = run_command(cmd, output);
  if (status < 0 && output.empty()) return Error{"Cycles peer: cannot run " + blender};
  CyclesRender r;
  std::string tail;
  bool timed = false;
  for (size_t at = 0; at < output.size();) {
    const size_t end = std::min(output.find('\n', at), output.size());
    const std::string line = output.substr(at, end - at);
    at = end + 1;
    if (!line.empty()) tail = line;
    double t = 0;
    char version[64] = {0};
    if (std::sscanf(line.c_str(), "FRAMELESS_CYCLES %lf %63s", &t, version) >= 1) {
      r.seconds = t;
      r.version = version;
      timed = true;
    }
  }
  if (status != 0 || !timed) {
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r')) tail.pop_back();
    return Error{"Cycles peer: blender failed (" + tail + ")"};
  }
  auto img = load_image(exr);
  if (!img) return Error{"Cycles peer: " + img.error().message};
  const Image& im = **img;
  if (im.width != width || im.height != height || im.channels < 3 || im.hdr.empty())
    return Error{"Cycles peer: " + exr + " is not a " + std::to_string(width) + "x" +
                 std::to_string(height) + " float RGB image"};
  r.width = width;
  r.height = height;
  r.rgb.resize(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int k = 0; k < 3; ++k) r.rgb[i * 3 + k] = im.hdr[i * size_t(im.channels) + k];
  return r;
}

}  // namespace frameless::bench
