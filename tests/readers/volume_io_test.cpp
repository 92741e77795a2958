// Raw and NRRD volumes (issue 27), written here by the test itself: every voxel type and byte
// order round trips, native data is memory-mapped, skips and gzip work, and every kind of broken
// file gets one line naming the file and the field, without allocating what it claims.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <new>
#include <random>
#include <tuple>

#include "core/io/volume_nrrd.h"
#include "core/io/volume_raw.h"

// The largest single allocation while a test watches (AllocationWatch): the readers must refuse
// a huge claimed volume before allocating it. Replacing operator new is global, so it only
// records while asked to.
namespace {
std::atomic<bool> g_watching{false};
std::atomic<size_t> g_largest_allocation{0};
}  // namespace

void* operator new(size_t n) {
  if (g_watching.load(std::memory_order_relaxed))
    for (size_t seen = g_largest_allocation.load(); n > seen && !g_largest_allocation.compare_exchange_weak(seen, n);) {
    }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// GCC sees free() meet memory from new once these inline; it is the malloc above.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace frameless {
namespace {

namespace fs = std::filesystem;

struct AllocationWatch {
  AllocationWatch() {
    g_largest_allocation = 0;
    g_watching = true;
  }
  ~AllocationWatch() { g_watching = false; }
  size_t largest() const { return g_largest_allocation.load(); }
};

// A folder of this process's own, removed at exit.
const fs::path& temp_folder() {
  struct Folder {
    fs::path path = fs::temp_directory_path() / ("frameless_volio_" + std::to_string(getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Folder folder;
  return folder.path;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const fs::path p = temp_folder() / name;
  std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  return p.string();
}

// True while `path` is mapped into this process (Linux lists mappings in /proc/self/maps).
bool is_mapped(const std::string& path) {
  std::ifstream maps("/proc/self/maps");
  const std::string text((std::istreambuf_iterator<char>(maps)), std::istreambuf_iterator<char>());
  return text.find(fs::canonical(path).string()) != std::string::npos;
}

// A gzip stream (window bits 15 + 16), or a zlib one (15).
std::string gzip(const std::string& raw, int window_bits = 15 + 16) {
  z_stream zs{};
  EXPECT_EQ(deflateInit2(&zs, 9, Z_DEFLATED, window_bits, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&zs, uLong(raw.size())), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  zs.avail_in = uInt(raw.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = uInt(out.size());
  EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

// 4x3x2 voxels, x fastest; voxel i holds value(i) in the file's type and byte order.
constexpr int kNx = 4, kNy = 3, kNz = 2, kVoxels = kNx * kNy * kNz;
float value(VoxelType type, int i) {
  return type == VoxelType::kUint8    ? float(i * 10 + 3)
         : type == VoxelType::kUint16 ? float(i * 1000 + 7)
                                      : i * 0.25f - 1.0f;
}

std::string voxel_bytes_of(VoxelType type, bool big_endian, int nan_at = -1) {
  std::string out;
  for (int i = 0; i < kVoxels; ++i) {
    char b[4];
    const float v = i == nan_at ? std::numeric_limits<float>::quiet_NaN() : value(type, i);
    const size_t n = voxel_bytes(type);
    const uint8_t u8 = n == 1 ? uint8_t(v) : 0;  // converted only into its own type (UBSan)
    const uint16_t u16 = n == 2 ? uint16_t(v) : 0;
    std::memcpy(b, n == 1 ? static_cast<const void*>(&u8) : n == 2 ? static_cast<const void*>(&u16) : &v, n);
    if (big_endian) std::reverse(b, b + n);  // this test runs little-endian (x86, ARM)
    out.append(b, n);
  }
  return out;
}

// A grid of the test's voxels.
void expect_test_grid(const Result<std::shared_ptr<const VolumeGrid>>& r, VoxelType type, Vec3 spacing = Vec3(1.0f)) {
  ASSERT_TRUE(r) << r.error().message;
  const VolumeGrid& g = *r.value();
  ASSERT_EQ(std::tuple(g.nx, g.ny, g.nz, int(g.type)), std::tuple(kNx, kNy, kNz, int(type)));
  EXPECT_EQ(g.spacing, spacing);
  for (int i = 0; i < kVoxels; ++i)
    ASSERT_EQ(g.at(i % kNx, i / kNx % kNy, i / (kNx * kNy)), value(type, i)) << "voxel " << i;
  EXPECT_EQ(g.min_value, value(type, 0));
  EXPECT_EQ(g.max_value, value(type, kVoxels - 1));
}

// A failure: one line, starting with `file`, saying `says`.
void expect_error(const Result<std::shared_ptr<const VolumeGrid>>& r, const std::string& file,
                  const std::string& says) {
  ASSERT_FALSE(r) << "expected an error saying '" << says << "'";
  const std::string& m = r.error().message;
  EXPECT_EQ(m.rfind(file, 0), 0u) << m;
  EXPECT_NE(m.find(says), std::string::npos) << "expected '" << says << "' in: " << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// ---- raw ----

TEST(RawVolume, EveryTypeAndByteOrderRoundTrips) {
  for (VoxelType type : {VoxelType::kUint8, VoxelType::kUint16, VoxelType::kFloat32})
    for (bool big : {false, true})
      for (uint64_t offset : {0, 3, 4}) {
        SCOPED_TRACE(std::string(voxel_type_name(type)) + (big ? " big" : " little") + " offset " +
                     std::to_string(offset));
        RawVolumeSpec spec{kNx, kNy, kNz, type, big, Vec3(0.5f, 1.0f, 2.0f), offset};
        const std::string bytes = std::string(offset, 'h') + voxel_bytes_of(type, big);
        const std::string path = write_file("v.raw", bytes);
        auto from_file = read_raw_volume(path, spec);
        ASSERT_TRUE(from_file) << from_file.error().message;
        expect_test_grid(from_file, type, spec.spacing);
        // Aligned data in this machine's byte order is mapped, not copied; the rest is owned.
        EXPECT_EQ(is_mapped(path), !voxels_need_swap(type, big) && offset % voxel_bytes(type) == 0);
        EXPECT_EQ(reinterpret_cast<uintptr_t>((*from_file)->storage->data()) % voxel_bytes(type), 0u);
        auto from_memory = decode_raw_volume(bytes, spec, "v.raw");
        ASSERT_TRUE(from_memory) << from_memory.error().message;
        expect_test_grid(from_memory, type, spec.spacing);
        ASSERT_EQ((*from_memory)->storage->size(), (*from_file)->storage->size());
        EXPECT_EQ(
            std::memcmp((*from_memory)->storage->data(), (*from_file)->storage->data(), kVoxels * voxel_bytes(type)),
            0);
        from_file = Error{"dropped"};  // the mapping lasts as long as the grid
        EXPECT_FALSE(is_mapped(path));
      }
}

TEST(RawVolume, AFileOfTheWrongSizeSaysBothSizes) {
  RawVolumeSpec spec{kNx, kNy, kNz, VoxelType::kUint16};
  const std::string short_path = write_file("short.raw", voxel_bytes_of(VoxelType::kUint16, false).substr(1));
  auto r = read_raw_volume(short_path, spec);
  expect_error(r, short_path, ": holds 47 bytes, expected 48 (48 bytes of 4x3x2 uint16 voxels)");
  spec.offset = 10;
  r = decode_raw_volume(std::string(100, '\0'), spec, "dir/long.raw");
  expect_error(r, "dir/long.raw", "holds 100 bytes, expected 58 (10 header bytes + 48 bytes of");
  r = read_raw_volume((temp_folder() / "absent.raw").string(), spec);
  expect_error(r, (temp_folder() / "absent.raw").string(), "cannot open");
  r = read_raw_volume("/dev/zero", spec);
  expect_error(r, "/dev/zero", "not a regular file");
}

TEST(RawVolume, HugeOrTinySidesAreRefusedBeforeAnythingIsAllocatedOrOpened) {
  struct Case {
    int64_t nx, ny, nz;
    std::string says;
  };
  for (const Case& c : {Case{2000000, 2000000, 2000000, "each must be at most 1048576"},
                        Case{1 << 20, 1 << 20, 2, "more than 2^34 voxels"}, Case{4, 3, 1, "each must be at least 2"},
                        Case{-5, 3, 2, "each must be at least 2"}}) {
    const RawVolumeSpec spec{c.nx, c.ny, c.nz, VoxelType::kFloat32};
    AllocationWatch watch;
    auto from_file = read_raw_volume("/nonexistent/huge.raw", spec);  // the sides fail before the open
    auto from_memory = decode_raw_volume("tiny", spec, "huge.raw");
    EXPECT_LT(watch.largest(), size_t(1) << 16);
    expect_error(from_file, "/nonexistent/huge.raw: dimensions", c.says);
    expect_error(from_memory, "huge.raw: dimensions", c.says);
  }
}

TEST(RawVolume, ANanVoxelIsNamed) {
  const RawVolumeSpec spec{kNx, kNy, kNz, VoxelType::kFloat32, true};
  const std::string path = write_file("nan.raw", voxel_bytes_of(VoxelType::kFloat32, true, 9));
  auto r = read_raw_volume(path, spec);
  expect_error(r, path, "voxel (1, 2, 0) is not a finite number");
}

// ---- NRRD ----

std::string u16_fields(const std::string& endian = "little", const std::string& encoding = "raw") {
  return "type: unsigned short\ndimension: 3\nsizes: 4 3 2\nencoding: " + encoding + "\nendian: " + endian + "\n";
}
std::string f32_fields(const std::string& encoding = "raw") {
  return "type: float\ndimension: 3\nsizes: 4 3 2\nencoding: " + encoding + "\nendian: little\n";
}
std::string u8_fields(const std::string& sizes) {
  return "type: uchar\ndimension: 3\nsizes: " + sizes + "\nencoding: raw\n";
}
std::string nrrd(const std::string& fields, const std::string& data = "") {
  return "NRRD0004\n" + fields + "\n" + data;
}

TEST(Nrrd, AttachedRawDataIsMappedWhenNativeAndAligned) {
  for (const std::string comment : {"", "#\n", "#a\n", "#ab\n"}) {
    const std::string header = "NRRD0004\n" + comment + f32_fields() + "\n";
    SCOPED_TRACE("header of " + std::to_string(header.size()) + " bytes");
    const std::string bytes = header + voxel_bytes_of(VoxelType::kFloat32, false);
    const std::string path = write_file("attached.nrrd", bytes);
    auto g = read_nrrd(path);
    ASSERT_TRUE(g) << g.error().message;
    expect_test_grid(g, VoxelType::kFloat32);
    EXPECT_EQ(is_mapped(path), header.size() % 4 == 0);  // else copied: mapped floats must be aligned
    EXPECT_EQ(reinterpret_cast<uintptr_t>((*g)->storage->data()) % 4, 0u);
    auto m = decode_nrrd(bytes, "attached.nrrd", "");
    expect_test_grid(m, VoxelType::kFloat32);
  }
}

TEST(Nrrd, EveryTypeNameAndByteOrderReads) {
  struct Case {
    std::string type_name;
    VoxelType type;
  };
  for (const Case& c : {Case{"uchar", VoxelType::kUint8}, Case{"unsigned char", VoxelType::kUint8},
                        Case{"uint8", VoxelType::kUint8}, Case{"uint8_t", VoxelType::kUint8},
                        Case{"ushort", VoxelType::kUint16}, Case{"unsigned short", VoxelType::kUint16},
                        Case{"uint16", VoxelType::kUint16}, Case{"uint16_t", VoxelType::kUint16},
                        Case{"unsigned short int", VoxelType::kUint16}, Case{"float", VoxelType::kFloat32}})
    for (bool big : {false, true})
      for (const std::string encoding : {"raw", "gzip", "gz"}) {
        SCOPED_TRACE(c.type_name + (big ? " big " : " little ") + encoding);
        const std::string data = voxel_bytes_of(c.type, big);
        const std::string fields = "type: " + c.type_name + "\ndimension: 3\nsizes: 4 3 2\nencoding: " + encoding +
                                   "\nendian: " + (big ? "big" : "little") + "\n";
        const std::string path = write_file("types.nrrd", nrrd(fields, encoding == "raw" ? data : gzip(data)));
        auto g = read_nrrd(path);
        expect_test_grid(g, c.type);
      }
}

TEST(Nrrd, DetachedHeadersFindTheirDataBesideThem) {
  const std::string data = voxel_bytes_of(VoxelType::kUint16, true);
  write_file("detached.raw", data);
  write_file("detached.raw.gz", gzip(data));
  const std::string raw_header =
      write_file("detached.nhdr", "NRRD0005\n" + u16_fields("big") + "data file: detached.raw\n");
  const std::string gz_header =
      write_file("detached_gz.nhdr", "NRRD0004\n" + u16_fields("big", "gzip") + "datafile: ./detached.raw.gz");
  for (const std::string& path : {raw_header, gz_header}) {
    auto g = read_nrrd(path);
    expect_test_grid(g, VoxelType::kUint16);
  }
  // Native 16-bit detached data is mapped, and stays 16-bit.
  write_file("native.raw", voxel_bytes_of(VoxelType::kUint16, false));
  const std::string native = write_file("native.nhdr", "NRRD0004\n" + u16_fields() + "data file: native.raw\n\n");
  auto g = read_nrrd(native);
  ASSERT_TRUE(g) << g.error().message;
  EXPECT_EQ((*g)->type, VoxelType::kUint16);
  EXPECT_TRUE(is_mapped((temp_folder() / "native.raw").string()));
  // decode_nrrd resolves the data file against the folder it is given.
  auto d =
      decode_nrrd("NRRD0004\n" + u16_fields("big") + "data file: detached.raw\n", "mem.nhdr", temp_folder().string());
  expect_test_grid(d, VoxelType::kUint16);
}

TEST(Nrrd, ZlibStreamsAreAcceptedAsGzip) {
  const std::string zlib_stream = gzip(voxel_bytes_of(VoxelType::kFloat32, false), 15);
  expect_test_grid(decode_nrrd(nrrd(f32_fields("gzip"), zlib_stream), "z.nrrd", ""), VoxelType::kFloat32);
}

TEST(Nrrd, SpacingsAndSpaceDirections) {
  const std::string data = voxel_bytes_of(VoxelType::kUint16, false);
  auto g = decode_nrrd(nrrd(u16_fields() + "spacings: 0.5 1 2.25\n", data), "s.nrrd", "");
  expect_test_grid(g, VoxelType::kUint16, Vec3(0.5f, 1.0f, 2.25f));
  const std::string directions =
      "space: right-anterior-superior\nspace directions: (0,0.5,0) (3,4,0)  ( 0, 0, -2 )\n"
      "space origin: (1,2,3)\n";
  g = decode_nrrd(nrrd(u16_fields() + directions, data), "d.nrrd", "");
  expect_test_grid(g, VoxelType::kUint16, Vec3(0.5f, 5.0f, 2.0f));
}

TEST(Nrrd, CommentsKeyValuesDescriptiveFieldsAndCrLf) {
  std::string header = "NRRD0004\n# made by hand\n" + u16_fields() +
                       "content: test:=not a key\nkinds: domain domain domain\nlabels: \"x\" \"y\" \"z\"\n"
                       "my key:=my: value\n#\n\n";
  std::string crlf;
  for (char c : header) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  for (const std::string& h : {header, crlf}) {
    auto g = decode_nrrd(h + voxel_bytes_of(VoxelType::kUint16, false), "c.nrrd", "");
    expect_test_grid(g, VoxelType::kUint16);
  }
}

TEST(Nrrd, LineSkipAndByteSkip) {
  const std::string data = voxel_bytes_of(VoxelType::kUint16, true);
  // A data file with a text header of its own: 2 lines, then 5 bytes.
  write_file("skips.dat", "P5 made up\n# two lines\n12345" + data);
  auto g = read_nrrd(write_file(
      "skips.nhdr", "NRRD0004\n" + u16_fields("big") + "data file: skips.dat\nline skip: 2\nbyte skip: 5\n"));
  expect_test_grid(g, VoxelType::kUint16);
  // byte skip -1: the data ends the file, whatever comes before it.
  g = read_nrrd(
      write_file("skips_end.nhdr", "NRRD0004\n" + u16_fields("big") + "data file: skips.dat\nbyte skip: -1\n"));
  expect_test_grid(g, VoxelType::kUint16);
  // Attached: the skips count from the blank line; native data after them is still mapped.
  const std::string attached =
      write_file("skips.nrrd", nrrd(u16_fields() + "line skip: 1\nbyte skip: 3\n",
                                    "junk line\nabc" + voxel_bytes_of(VoxelType::kUint16, false)));
  g = read_nrrd(attached);
  expect_test_grid(g, VoxelType::kUint16);
  const size_t data_at = nrrd(u16_fields() + "line skip: 1\nbyte skip: 3\n").size() + 13;
  EXPECT_EQ(is_mapped(attached), data_at % 2 == 0);
  // gzip: the line skip is in the file, the byte skip in the inflated data.
  g = decode_nrrd(nrrd(u16_fields("big", "gzip") + "line skip: 1\nbyte skip: 7\n", "text\n" + gzip("1234567" + data)),
                  "gz.nrrd", "");
  expect_test_grid(g, VoxelType::kUint16);
}

TEST(Nrrd, BrokenFilesGetOneLineNamingTheFileAndTheField) {
  const std::string data = voxel_bytes_of(VoxelType::kUint16, false);
  const std::string gz = gzip(data);
  std::string corrupt = gz;
  corrupt[10] = char(0xff);  // the first deflate block's type becomes the reserved 3
  const std::string fdata = voxel_bytes_of(VoxelType::kFloat32, false, 9);
  struct Case {
    std::string bytes, says;
  };
  const std::vector<Case> cases = {
      {nrrd(u16_fields(), data.substr(1)), "dir/vol.nrrd: sizes 4x3x2 uint16 need 48 bytes of data, the data holds 47"},
      {nrrd(u16_fields(), data + "x"), "dir/vol.nrrd: sizes 4x3x2 uint16 need 48 bytes of data, the data holds 49"},
      {nrrd("type: double\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n", data + data + data + data),
       "dir/vol.nrrd:2: type: unsupported type 'double'"},
      {nrrd("type: short\ndimension: 3\nsizes: 4 3 2\nencoding: raw\nendian: little\n", data),
       ":2: type: unsupported type"},
      {nrrd(u16_fields("little", "ascii"), "1 2 3"), "dir/vol.nrrd:5: encoding: unsupported encoding 'ascii'"},
      {nrrd(u16_fields("little", "bzip2"), data), ":5: encoding: unsupported encoding 'bzip2'"},
      {nrrd(u16_fields("little", "gzip"), gz.substr(0, gz.size() - 10)), "dir/vol.nrrd: gzip data is truncated"},
      {nrrd(u16_fields("little", "gzip"), corrupt), "dir/vol.nrrd: gzip data is corrupt: invalid block type"},
      {nrrd(u16_fields("little", "gzip"), gzip(data + "x")),
       "gzip data holds more than the 48 bytes sizes 4x3x2 uint16 need"},
      {nrrd(u16_fields("little", "gzip"), gzip(data.substr(2))), "gzip data holds 46 bytes, not the 48 bytes sizes"},
      {nrrd(u16_fields("little", "gzip"), gz + "tail"), "4 bytes follow the end of the gzip data"},
      {nrrd("type: uchar\ndimension: 2\nsizes: 4 3\nencoding: raw\n", "abcdefghijkl"),
       ":3: dimension: must be 3 (a volume), not 2"},
      {nrrd("type: uchar\ndimension: three\n"), ":3: dimension: not an integer: 'three'"},
      {nrrd("type: uchar\ndimension: 3\nencoding: raw\n", data), "dir/vol.nrrd: sizes: missing field"},
      {nrrd("dimension: 3\nsizes: 4 3 2\nencoding: raw\n", data), "dir/vol.nrrd: type: missing field"},
      {nrrd("type: ushort\ndimension: 3\nsizes: 4 3 2\nencoding: raw\n", data), "dir/vol.nrrd: endian: missing field"},
      {"NRRD0009\n" + u16_fields() + "\n" + data, "dir/vol.nrrd:1: magic: not a NRRD file"},
      {"P5\n4 3\n255\n", "dir/vol.nrrd:1: magic: not a NRRD file"},
      {"", "dir/vol.nrrd:1: magic"},
      {nrrd(u16_fields() + "type: uchar\n", data), "dir/vol.nrrd:7: type: duplicate field (first on line 2)"},
      {nrrd(u16_fields() + "data file: missing.raw\n"),
       "dir/vol.nrrd:7: data file: '" + temp_folder().string() + "/missing.raw': cannot open: No such file"},
      {nrrd(u16_fields() + "data file: LIST\n"), ":7: data file: LIST data files"},
      {nrrd(u16_fields() + "data file: slice%03d.raw 1 2 1\n"), ":7: data file: format-string data files"},
      {nrrd(u16_fields("little", "gzip") + "byte skip: -1\n", gz),
       ":7: byte skip: -1 (data at the end of the file) needs raw encoding"},
      {nrrd(u16_fields() + "byte skip: -2\n", data), ":7: byte skip: expected a non-negative integer or -1"},
      {nrrd(u16_fields() + "byte skip: 100\n", data),
       "sizes 4x3x2 uint16 need 48 bytes of data, the data holds none after its byte skip"},
      {nrrd(u16_fields() + "line skip: 3\n", "one\ntwo\n"), ":7: line skip: the data ends before line 3"},
      {nrrd(u16_fields() + "colour: red\n", data), ":7: colour: unknown field"},
      {nrrd(u16_fields() + "hello\n", data), ":7: 'hello': not a 'field: value' line"},
      {nrrd(u8_fields("4 3 1"), data), ":4: sizes: dimensions 4x3x1: each must be at least 2"},
      {nrrd(u8_fields("2000000 2000000 2000000"), data),
       ":4: sizes: dimensions 2000000x2000000x2000000: each must be at most"},
      {nrrd(u8_fields("4 3 -2"), data), ":4: sizes: expected 3 positive integers"},
      {nrrd(u16_fields() + "spacings: 1 -1 1\n", data), ":7: spacings: expected 3 positive numbers, not '1 -1 1'"},
      {nrrd(u16_fields() + "spacings: 1 nan 1\n", data), ":7: spacings: expected 3 positive numbers"},
      {nrrd(u16_fields() + "space directions: (1,0,0) none (0,0,1)\n", data),
       ":7: space directions: expected 3 vectors"},
      {nrrd(u16_fields() + "space directions: (1,0,0) (0,0,0) (0,0,1)\n", data),
       ":7: space directions: expected 3 vectors"},
      {nrrd(u16_fields() + "space directions: (1,0) (0,1) (0,0)\n", data), ":7: space directions: expected 3 vectors"},
      {nrrd(u16_fields() + "spacings: 1 1 1\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n", data),
       ":8: space directions: give spacings or space directions, not both"},
      {nrrd(f32_fields(), fdata), "dir/vol.nrrd: voxel (1, 2, 0) is not a finite number"},
      {"NRRD0004\n" + u16_fields(),
       "dir/vol.nrrd: the header has no blank line before its data and names no data file"},
  };
  for (const Case& c : cases) {
    auto r = decode_nrrd(c.bytes, "dir/vol.nrrd", temp_folder().string());
    expect_error(r, "dir/vol.nrrd", c.says);
  }
}

TEST(Nrrd, BrokenFilesOnDiskNameTheirFiles) {
  const std::string data = voxel_bytes_of(VoxelType::kUint16, false);
  const std::string gz = gzip(data);
  const std::string truncated =
      write_file("truncated.nrrd", nrrd(u16_fields("little", "gzip"), gz.substr(0, gz.size() / 2)));
  auto r = read_nrrd(truncated);
  expect_error(r, truncated, ": gzip data is truncated");
  write_file("short.raw", data.substr(4));
  const std::string detached = write_file("short.nhdr", "NRRD0004\n" + u16_fields() + "data file: short.raw\n");
  r = read_nrrd(detached);
  expect_error(r, detached,
               ": data file '" + (temp_folder() / "short.raw").string() +
                   "': sizes 4x3x2 uint16 need 48 bytes of data, the data holds 44");
  const std::string orphan = write_file("orphan.nhdr", "NRRD0004\n" + u16_fields() + "data file: gone.raw\n");
  r = read_nrrd(orphan);
  expect_error(r, orphan, ":7: data file: '" + (temp_folder() / "gone.raw").string() + "': cannot open");
  r = read_nrrd((temp_folder() / "absent.nrrd").string());
  expect_error(r, (temp_folder() / "absent.nrrd").string(), ": cannot open: No such file");
  r = decode_nrrd(nrrd(u16_fields() + "data file: /dev/zero\n"), "dev.nhdr", "");
  expect_error(r, "dev.nhdr:7: data file: '/dev/zero'", "not a regular file");
}

TEST(Nrrd, AShortStreamClaimingAHugeVolumeAllocatesLittle) {
  // 512 MiB of uint8 claimed; a gzip stream of a few bytes cut short. Inflating grows its buffer
  // as data arrives, so the claim costs about a megabyte.
  const std::string gz = gzip(std::string(4096, 'a'));
  const std::string bytes =
      nrrd("type: uchar\ndimension: 3\nsizes: 1024 1024 512\nencoding: gzip\n", gz.substr(0, gz.size() - 4));
  AllocationWatch watch;
  auto r = decode_nrrd(bytes, "bomb.nrrd", "");
  EXPECT_LE(watch.largest(), size_t(2) << 20);
  EXPECT_GE(watch.largest(), size_t(1) << 20);  // the watch works: it saw the first 1 MiB step
  expect_error(r, "bomb.nrrd", "gzip data is truncated");
}

// Every prefix of good files, their byte mutations and random header soup: a grid or one line.
TEST(Nrrd, PrefixesMutationsAndGarbageNeverCrash) {
  const std::vector<std::string> good = {
      nrrd(u16_fields("big"), voxel_bytes_of(VoxelType::kUint16, true)),
      nrrd(u16_fields("little", "gzip") + "spacings: 1 2 3\n", gzip(voxel_bytes_of(VoxelType::kUint16, false))),
      nrrd("type: float\ndimension: 3\nsizes: 4 3 2\nencoding: gz\nendian: big\nbyte skip: 2\n",
           gzip("xx" + voxel_bytes_of(VoxelType::kFloat32, true)))};
  const auto check = [](const std::string& bytes) {
    auto r = decode_nrrd(bytes, "f.nrrd", "/nonexistent");
    if (r) {
      const VolumeGrid& g = **r;
      EXPECT_EQ(g.storage->size(), g.voxels() * voxel_bytes(g.type));
      EXPECT_LE(g.min_value, g.max_value);
      return true;
    }
    EXPECT_EQ(r.error().message.rfind("f.nrrd", 0), 0u) << r.error().message;
    EXPECT_EQ(r.error().message.find_first_of("\n\r"), std::string::npos) << r.error().message;
    return false;
  };
  for (const std::string& file : good) {
    ASSERT_TRUE(check(file));
    for (size_t n = 0; n < file.size(); ++n) EXPECT_FALSE(check(file.substr(0, n))) << "prefix of " << n << " bytes";
  }
  std::mt19937 rng(27);
  for (int k = 0; k < 3000; ++k) {
    std::string m = good[size_t(k) % good.size()];
    for (int e = 1 + int(rng() % 4); e > 0; --e) m[rng() % m.size()] = char(rng());
    check(m);
  }
  // clang-format off
  const std::vector<std::string> soup = {
      "type: uchar", "type: float", "dimension: 3", "sizes: 2 2 2", "sizes: 9999 2 2", "encoding: raw",
      "encoding: gzip", "endian: big", "byte skip: -1", "line skip: 2", "spacings: 1 1 1", "data file: x",
      "space directions: (1,0,0) (0,1,0) (0,0,1)", "data file: /dev/zero", "# c", "k:=v", "", "\r", ":", ": ",
      "\x1f\x8b\x08"};
  // clang-format on
  for (int k = 0; k < 3000; ++k) {
    std::string s = "NRRD0004\n";
    for (int lines = int(rng() % 10); lines > 0; --lines) s += soup[rng() % soup.size()] + "\n";
    for (int b = int(rng() % 40); b > 0; --b) s += char(rng());
    check(s);
    std::string garbage(rng() % 64, '\0');
    for (char& c : garbage) c = char(rng());
    check(garbage);
  }
}

}  // namespace
}  // namespace frameless
