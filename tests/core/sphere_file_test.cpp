// Binary sphere files (sphere_file.h): the documented layout, write/read round trips with and
// without scalars, the colour map, appending, and a one-line error (file, record, problem) that
// leaves the geometry as it was for every kind of malformed file.
#include "core/io/sphere_file.h"

#include <gtest/gtest.h>

#include <dirent.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace frameless {
namespace {

class TempDir {
 public:
  TempDir() {
    std::string pattern = ::testing::TempDir() + "sphere_file_XXXXXX";
    path_ = mkdtemp(pattern.data()) ? pattern : "";
  }
  ~TempDir() {
    if (path_.empty()) return;
    for (const std::string& f : files()) std::remove((path_ + "/" + f).c_str());
    rmdir(path_.c_str());
  }
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    if (DIR* d = opendir(path_.c_str())) {
      while (dirent* e = readdir(d))
        if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0)
          out.push_back(e->d_name);
      closedir(d);
    }
    return out;
  }

 private:
  std::string path_;
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

void put_u32(std::string& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = char((v >> (8 * i)) & 0xff);
}
void put_u64(std::string& b, size_t at, uint64_t v) {
  put_u32(b, at, uint32_t(v));
  put_u32(b, at + 4, uint32_t(v >> 32));
}
void put_f32(std::string& b, size_t at, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put_u32(b, at, u);
}

// A well-formed file in memory, built byte by byte from the documented layout (independently of
// write_sphere_file): `n` records, with scalars when record == 20.
std::string file_bytes(uint32_t n, uint32_t record) {
  std::string b(32 + size_t(n) * record, '\0');
  std::memcpy(b.data(), "FLSPHERE", 8);
  put_u32(b, 8, 1);
  put_u32(b, 12, record);
  put_u64(b, 16, n);
  for (uint32_t i = 0; i < n; ++i) {
    const size_t at = 32 + size_t(i) * record;
    put_f32(b, at, float(i));
    put_f32(b, at + 4, -float(i));
    put_f32(b, at + 8, 0.5f * float(i));
    put_f32(b, at + 12, 0.25f + float(i % 3));
    if (record == 20) put_f32(b, at + 16, 10.0f * float(i));
  }
  return b;
}

std::vector<Sphere> sample_spheres() {
  return {{{0.0f, 0.0f, 0.0f}, 1.0f},
          {{1.5f, -2.25f, 3e7f}, 0.0f},  // zero radius is accepted
          {{-1e-30f, 1e30f, 7.0f}, 1e-20f},
          {{0.1f, 0.2f, 0.3f}, -0.0f},  // negative zero is zero
          {{std::numeric_limits<float>::max(), -1.0f, 2.0f}, 3.0f},
          {{4.0f, 5.0f, 6.0f}, 123456.0f}};
}

bool same_bits(const std::vector<Sphere>& a, const std::vector<Sphere>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Sphere)) == 0;
}

// Geometry that already holds two spheres with materials: an error must leave it exactly so.
Geometry prefilled() {
  Geometry g;
  g.spheres = {{{9.0f, 9.0f, 9.0f}, 1.0f}, {{8.0f, 8.0f, 8.0f}, 2.0f}};
  g.sphere_material = {4, 5};
  return g;
}

TEST(SphereFile, LayoutIsTheDocumentedOne) {
  TempDir dir;
  ASSERT_FALSE(dir.path().empty());
  const std::vector<Sphere> s = {{{1.0f, 2.0f, 3.0f}, 4.0f}, {{5.0f, 6.0f, 7.0f}, 8.0f}};
  std::string error;
  ASSERT_TRUE(write_sphere_file(dir.file("a.spheres"), s, nullptr, &error)) << error;
  // "FLSPHERE", version 1, record 16, count 2, reserved 0, then x y z r per record.
  std::string expect = file_bytes(0, 16);
  put_u64(expect, 16, 2);
  expect.resize(32 + 2 * 16);
  for (int i = 0; i < 8; ++i) put_f32(expect, 32 + 4 * size_t(i), float(i + 1));
  EXPECT_EQ(read_all(dir.file("a.spheres")), expect);
  const std::vector<float> scalars = {-1.0f, 2.5f};
  ASSERT_TRUE(write_sphere_file(dir.file("b.spheres"), s, &scalars, &error)) << error;
  const std::string b = read_all(dir.file("b.spheres"));
  ASSERT_EQ(b.size(), 32u + 2 * 20);
  EXPECT_EQ(b.substr(0, 8), "FLSPHERE");
  EXPECT_EQ(b[12], 20);
  float f;
  std::memcpy(&f, b.data() + 32 + 20 + 16, 4);
  EXPECT_EQ(f, 2.5f);
  std::memcpy(&f, b.data() + 32 + 20 + 12, 4);
  EXPECT_EQ(f, 8.0f);
}

TEST(SphereFile, RoundTripWithoutScalars) {
  TempDir dir;
  const std::vector<Sphere> s = sample_spheres();
  std::string error;
  ASSERT_TRUE(write_sphere_file(dir.file("s.spheres"), s, nullptr, &error)) << error;
  EXPECT_EQ(dir.files(), std::vector<std::string>{"s.spheres"});  // no temporary left behind
  Geometry g;
  auto info = load_sphere_file(dir.file("s.spheres"), g);
  ASSERT_TRUE(info.ok()) << info.error().message;
  EXPECT_EQ(info->count, s.size());
  EXPECT_FALSE(info->has_scalar);
  EXPECT_TRUE(same_bits(g.spheres, s));
  EXPECT_TRUE(g.sphere_material.empty());  // material 0 for all, not stored
  // A first material other than 0 is stored for every sphere.
  Geometry h;
  ASSERT_TRUE(load_sphere_file(dir.file("s.spheres"), h, 3).ok());
  EXPECT_EQ(h.sphere_material, std::vector<uint16_t>(s.size(), 3));
  // Empty set.
  ASSERT_TRUE(write_sphere_file(dir.file("e.spheres"), {}, nullptr, &error)) << error;
  Geometry e;
  auto ie = load_sphere_file(dir.file("e.spheres"), e);
  ASSERT_TRUE(ie.ok()) << ie.error().message;
  EXPECT_EQ(ie->count, 0u);
  EXPECT_TRUE(e.spheres.empty());
}

TEST(SphereFile, RoundTripWithScalarsThroughTheColourMap) {
  TempDir dir;
  std::vector<Sphere> s;
  std::vector<float> scalars;
  for (int i = 0; i < 100; ++i) {
    s.push_back({{float(i), 0.0f, 0.0f}, 0.5f});
    scalars.push_back(float(i) - 20.0f);  // -20 .. 79
  }
  std::string error;
  ASSERT_TRUE(write_sphere_file(dir.file("c.spheres"), s, &scalars, &error)) << error;
  Geometry g;
  auto info = load_sphere_file(dir.file("c.spheres"), g, 3, 10);
  ASSERT_TRUE(info.ok()) << info.error().message;
  EXPECT_TRUE(info->has_scalar);
  EXPECT_EQ(info->scalar_min, -20.0f);
  EXPECT_EQ(info->scalar_max, 79.0f);
  EXPECT_TRUE(same_bits(g.spheres, s));
  ASSERT_EQ(g.sphere_material.size(), s.size());
  for (int i = 0; i < 100; ++i) {
    const int expect = std::min(9, int(double(i) / 99.0 * 10.0));
    EXPECT_EQ(g.sphere_material[i], 3 + expect) << i;
  }
  EXPECT_EQ(g.sphere_material.front(), 3);
  EXPECT_EQ(g.sphere_material.back(), 12);
  // Scalars but no colour map: the range is reported, materials are not made.
  Geometry plain;
  auto pi = load_sphere_file(dir.file("c.spheres"), plain);
  ASSERT_TRUE(pi.ok());
  EXPECT_EQ(pi->scalar_max, 79.0f);
  EXPECT_TRUE(plain.sphere_material.empty());
  // A constant scalar maps to the first colour.
  std::vector<float> same(s.size(), 7.0f);
  ASSERT_TRUE(write_sphere_file(dir.file("k.spheres"), s, &same, &error)) << error;
  Geometry k;
  ASSERT_TRUE(load_sphere_file(dir.file("k.spheres"), k, 2, 8).ok());
  EXPECT_EQ(k.sphere_material, std::vector<uint16_t>(s.size(), 2));
}

TEST(SphereFile, AppendsAndKeepsMaterialsConsistent) {
  const std::string plain = file_bytes(5, 16), scalar = file_bytes(5, 20);
  Geometry g = prefilled();
  ASSERT_TRUE(parse_sphere_bytes(plain, "p", g).ok());
  EXPECT_EQ(g.spheres.size(), 7u);
  EXPECT_EQ(g.sphere_material, (std::vector<uint16_t>{4, 5, 0, 0, 0, 0, 0}));
  Geometry h;
  h.spheres = {{{1.0f, 1.0f, 1.0f}, 1.0f}};  // no material array: material 0
  ASSERT_TRUE(parse_sphere_bytes(scalar, "s", h, 1, 5).ok());
  EXPECT_EQ(h.sphere_material, (std::vector<uint16_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(h.spheres[3].center, Vec3(2.0f, -2.0f, 1.0f));
  EXPECT_EQ(h.spheres[3].radius, 2.25f);
}

TEST(SphereFile, BytesAndFileGiveTheSame) {
  TempDir dir;
  const std::string bytes = file_bytes(300000, 20);  // more than one 1 MiB read block
  write_all(dir.file("big.spheres"), bytes);
  Geometry a, b;
  auto ia = parse_sphere_bytes(bytes, "x", a, 0, 16);
  auto ib = load_sphere_file(dir.file("big.spheres"), b, 0, 16);
  ASSERT_TRUE(ia.ok() && ib.ok());
  EXPECT_TRUE(same_bits(a.spheres, b.spheres));
  EXPECT_EQ(a.sphere_material, b.sphere_material);
  EXPECT_EQ(a.spheres.size(), 300000u);
  EXPECT_EQ(a.spheres.capacity(), 300000u);  // reserved exactly, no growth
  EXPECT_EQ(a.spheres[299999].center.x, 299999.0f);
  EXPECT_EQ(b.sphere_material.back(), 15);
}

struct BadCase {
  const char* what;
  std::string bytes;
  std::string message;  // after "NAME: "
  int colormap = 0;
};

std::vector<BadCase> bad_cases() {
  std::vector<BadCase> v;
  const std::string good16 = file_bytes(4, 16), good20 = file_bytes(4, 20);
  auto with = [](std::string b, size_t at, float f) {
    put_f32(b, at, f);
    return b;
  };
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
  v.push_back({"empty", "", "header: file is 0 bytes, shorter than the 32-byte header"});
  v.push_back({"short header", good16.substr(0, 31),
               "header: file is 31 bytes, shorter than the 32-byte header"});
  std::string magic = good16;
  magic[0] = 'X';
  v.push_back({"magic", magic, "header: magic is not FLSPHERE (not a frameless sphere file)"});
  std::string version = good16;
  put_u32(version, 8, 2);
  v.push_back({"version", version, "header: version 2 is not supported (expected 1)"});
  std::string record = good16;
  put_u32(record, 12, 24);
  v.push_back({"record size", record,
               "header: record size 24 is not 16 (x y z radius) or 20 (x y z radius scalar)"});
  std::string reserved = good16;
  reserved[30] = 1;
  v.push_back({"reserved", reserved, "header: reserved field is not zero"});
  v.push_back({"truncated", good16.substr(0, good16.size() - 1),
               "size 95 is not header + count * record (32 + 4 * 16 = 96 bytes)"});
  v.push_back({"trailing byte", good16 + "x",
               "size 97 is not header + count * record (32 + 4 * 16 = 96 bytes)"});
  v.push_back({"partial record", good20.substr(0, 32 + 3 * 20 + 16),
               "size 108 is not header + count * record (32 + 4 * 20 = 112 bytes)"});
  std::string huge = good16;
  put_u64(huge, 16, uint64_t(1) << 62);
  v.push_back({"huge count", huge,
               "size 96 is not header + count * record (32 + 4611686018427387904 * 16 = more "
               "than 2^64 bytes)"});
  std::string big = good16;
  put_u64(big, 16, uint64_t(1) << 33);
  v.push_back({"big count", big,
               "size 96 is not header + count * record (32 + 8589934592 * 16 = 137438953504 "
               "bytes)"});
  v.push_back({"NaN radius", with(good16, 32 + 2 * 16 + 12, nan), "record 2: radius is NaN"});
  v.push_back({"negative radius", with(good16, 32 + 3 * 16 + 12, -0.5f),
               "record 3: radius is negative (-0.5)"});
  v.push_back({"infinite radius", with(good20, 32 + 1 * 20 + 12, inf),
               "record 1: radius is infinite"});
  v.push_back({"NaN x", with(good16, 32, nan), "record 0: x is NaN"});
  v.push_back({"infinite y", with(good20, 32 + 2 * 20 + 4, inf), "record 2: y is infinite"});
  v.push_back({"-infinite z", with(good16, 32 + 3 * 16 + 8, -inf), "record 3: z is infinite"});
  v.push_back({"NaN scalar", with(good20, 32 + 1 * 20 + 16, nan), "record 1: scalar is NaN"});
  v.push_back({"infinite scalar", with(good20, 32 + 3 * 20 + 16, -inf),
               "record 3: scalar is infinite", 8});
  v.push_back({"colour map past 65535", good20,
               "colour map: materials 0 + 70000 do not fit in 16-bit material ids", 70000});
  return v;
}

TEST(SphereFile, EachMalformedInputGivesItsOneLineError) {
  for (const BadCase& c : bad_cases()) {
    SCOPED_TRACE(c.what);
    Geometry g = prefilled();
    const Geometry before = g;
    auto r = parse_sphere_bytes(c.bytes, "bad.spheres", g, 0, c.colormap);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "bad.spheres: " + c.message);
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
    EXPECT_TRUE(same_bits(g.spheres, before.spheres));
    EXPECT_EQ(g.sphere_material, before.sphere_material);
    // With an empty geometry too (no material array to restore).
    Geometry e;
    ASSERT_FALSE(parse_sphere_bytes(c.bytes, "bad.spheres", e, 0, c.colormap).ok());
    EXPECT_TRUE(e.spheres.empty());
    EXPECT_TRUE(e.sphere_material.empty());
  }
}

TEST(SphereFile, FileErrorsNameThePath) {
  TempDir dir;
  const std::string path = dir.file("bad\nname.spheres");  // a line break stays on one line
  write_all(path, file_bytes(3, 16).substr(0, 60));
  Geometry g = prefilled();
  auto r = load_sphere_file(path, g);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, dir.path() + "/bad\\nname.spheres: size 60 is not header + count * "
                                            "record (32 + 3 * 16 = 80 bytes)");
  EXPECT_EQ(g.spheres.size(), 2u);
  std::string bytes = file_bytes(3, 16);
  put_f32(bytes, 32 + 16 + 12, std::numeric_limits<float>::quiet_NaN());
  write_all(dir.file("nan.spheres"), bytes);
  auto n = load_sphere_file(dir.file("nan.spheres"), g);
  ASSERT_FALSE(n.ok());
  EXPECT_EQ(n.error().message, dir.file("nan.spheres") + ": record 1: radius is NaN");
  EXPECT_EQ(g.spheres.size(), 2u);
  EXPECT_EQ(g.sphere_material.size(), 2u);
  auto missing = load_sphere_file(dir.file("none.spheres"), g);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message,
            dir.file("none.spheres") + ": cannot open: No such file or directory");
  auto directory = load_sphere_file(dir.path(), g);
  ASSERT_FALSE(directory.ok());
  EXPECT_EQ(directory.error().message, dir.path() + ": not a regular file");
}

TEST(SphereFile, CountBeyondWhatASceneHoldsIsRejectedBeforeAllocating) {
  // A sparse file whose size matches 2^32 records: the size check passes, the count check stops
  // it (no 64 GiB allocation is attempted, nothing is read).
  TempDir dir;
  const std::string path = dir.file("sparse.spheres");
  std::string header = file_bytes(0, 16);
  put_u64(header, 16, uint64_t(1) << 32);
  write_all(path, header);
  if (truncate(path.c_str(), off_t(32 + (uint64_t(1) << 36))) != 0)
    GTEST_SKIP() << "no sparse 64 GiB file here";
  Geometry g;
  auto r = load_sphere_file(path, g);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, path + ": header: count 4294967296 is more than a scene can hold "
                                      "(4294967294 primitives in all)");
  EXPECT_TRUE(g.spheres.empty());
  EXPECT_EQ(g.spheres.capacity(), 0u);
}

TEST(SphereFile, WriterErrors) {
  TempDir dir;
  std::string error;
  const std::vector<Sphere> s = sample_spheres();
  const std::vector<float> short_scalars(2, 1.0f);
  EXPECT_FALSE(write_sphere_file(dir.file("x.spheres"), s, &short_scalars, &error));
  EXPECT_EQ(error, dir.file("x.spheres") + ": scalars: 2 values for 6 spheres");
  EXPECT_FALSE(write_sphere_file(dir.file("no/such/dir.spheres"), s, nullptr, &error));
  EXPECT_NE(error.find("no/such/dir.spheres: cannot create temporary file"), std::string::npos);
  EXPECT_TRUE(dir.files().empty());
  // Replacing a file is atomic: the old content until the rename, then the new.
  ASSERT_TRUE(write_sphere_file(dir.file("r.spheres"), s, nullptr, &error)) << error;
  ASSERT_TRUE(write_sphere_file(dir.file("r.spheres"), {s[0]}, nullptr, &error)) << error;
  EXPECT_EQ(dir.files(), std::vector<std::string>{"r.spheres"});
  Geometry g;
  ASSERT_TRUE(load_sphere_file(dir.file("r.spheres"), g).ok());
  EXPECT_EQ(g.spheres.size(), 1u);
}

TEST(SphereFile, FailedWriteLeavesNothingBehind) {
  // A file size limit makes write(2) fail part way (EFBIG once SIGXFSZ is ignored).
  TempDir dir;
  std::string error;
  const std::vector<Sphere> one = {{{1.0f, 2.0f, 3.0f}, 4.0f}};
  ASSERT_TRUE(write_sphere_file(dir.file("old.spheres"), one, nullptr, &error)) << error;
  const std::vector<Sphere> many(100000, Sphere{{1.0f, 2.0f, 3.0f}, 4.0f});
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit small = saved;
  small.rlim_cur = 100000;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const bool ok = write_sphere_file(dir.file("old.spheres"), many, nullptr, &error);
  setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_FALSE(ok);
  EXPECT_NE(error.find("old.spheres: write failed: File too large"), std::string::npos) << error;
  EXPECT_EQ(dir.files(), std::vector<std::string>{"old.spheres"});  // temporary removed
  Geometry g;
  ASSERT_TRUE(load_sphere_file(dir.file("old.spheres"), g).ok());  // the old file is intact
  EXPECT_EQ(g.spheres.size(), 1u);
}

TEST(SphereFile, ColourMapIsViridisLike) {
  EXPECT_TRUE(colormap_colors(0).empty());
  ASSERT_EQ(colormap_colors(1).size(), 1u);
  const std::vector<Vec3> c = colormap_colors(32);
  ASSERT_EQ(c.size(), 32u);
  auto luminance = [](const Vec3& v) { return 0.2126f * v.x + 0.7152f * v.y + 0.0722f * v.z; };
  for (size_t i = 0; i < c.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(c[i][a], 0.0f);
      EXPECT_LE(c[i][a], 1.0f);
    }
    if (i > 0) {
      EXPECT_GT(luminance(c[i]), luminance(c[i - 1])) << i;  // dark to light
    }
  }
  EXPECT_GT(c.front().z, c.front().y);  // dark violet-blue
  EXPECT_GT(c.back().x, 0.9f);          // bright yellow
  EXPECT_LT(c.back().z, 0.1f);
}

}  // namespace
}  // namespace frameless
