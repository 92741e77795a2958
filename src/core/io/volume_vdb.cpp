// OpenVDB files: header, grid descriptors, the chosen grid's metadata, map and tree (topology,
// then the leaves' values), then the bricked grid. Layout as OpenVDB 10's io/Archive, io/File,
// math/Maps and tree/{Root,Internal,Leaf}Node write it.
#include "core/io/volume_vdb.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <new>

#include "core/io/vdb_values.h"

namespace frameless {
namespace {

using vdb::Cursor;
using vdb::Mask;
using vdb::Stored;
using vdb::VdbFailure;

constexpr int64_t kMagic = 0x56444220;   // " BDV"
constexpr uint32_t kFirstVersion = 222;  // OpenVDB 3.0: per-grid compression, node value codes

[[noreturn]] void fail(const std::string& what) { throw VdbFailure{what}; }
std::string byte_at(const Cursor& c) { return " (byte " + std::to_string(c.pos()) + ")"; }

struct Descriptor {
  std::string name, type, parent;
  uint64_t grid_pos = 0, block_pos = 0, end_pos = 0;
};

// OpenVDB makes duplicate names unique with a suffix after the record separator.
std::string plain_name(const std::string& s) { return s.substr(0, s.find('\x1e')); }

// Skips a metadata map; keeps the "class" string when asked.
void read_metadata(Cursor& c, std::string* grid_class) {
  const uint32_t n = c.get<uint32_t>("the metadata count");
  if (n > c.left() / 12)
    fail("a metadata count of " + std::to_string(n) + " that the file cannot hold" + byte_at(c));
  for (uint32_t i = 0; i < n; ++i) {
    const std::string name = c.string("a metadata name"), type = c.string("a metadata type");
    const uint32_t size = c.get<uint32_t>("a metadata size");
    const uint8_t* value = c.take(size, "a metadata value");
    if (grid_class && name == "class" && type == "string")
      grid_class->assign(reinterpret_cast<const char*>(value), size);
  }
}

Vec3 read_vec3d(Cursor& c, const char* what) {
  double v[3];
  std::memcpy(v, c.take(24, what), 24);
  return Vec3(float(v[0]), float(v[1]), float(v[2]));
}

// The grid's map (index -> world) as an affine transform; linear maps only.
Affine read_map(Cursor& c) {
  const std::string type = c.string("the map type");
  Affine a;
  if (type == "UniformScaleMap" || type == "ScaleMap" || type == "UniformScaleTranslateMap" ||
      type == "ScaleTranslateMap") {
    if (type.find("Translate") != std::string::npos) a.t = read_vec3d(c, "the map");
    const Vec3 s = read_vec3d(c, "the map");
    c.take(4 * 24, "the map");  // voxel size, inverse scale and two derived vectors
    a.m = glm::mat3(glm::vec3(s.x, 0, 0), glm::vec3(0, s.y, 0), glm::vec3(0, 0, s.z));
  } else if (type == "TranslationMap") {
    a.t = read_vec3d(c, "the map");
  } else if (type == "AffineMap" || type == "UnitaryMap") {
    double m[16];  // row-major, row vectors: world = [i j k 1] m
    std::memcpy(m, c.take(128, "the map"), 128);
    if (m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0)
      fail("an affine map whose last column is not (0, 0, 0, 1)");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a.m[i][j] = float(m[4 * i + j]);
    a.t = Vec3(float(m[12]), float(m[13]), float(m[14]));
  } else if (type == "NonlinearFrustumMap") {
    fail("a frustum map (only linear maps are read)");
  } else {
    fail("unknown map type '" + type.substr(0, 60) + "'");
  }
  const float det = glm::determinant(a.m);
  if (!std::isfinite(det) || std::abs(det) < 1e-30f || !std::isfinite(a.t.x + a.t.y + a.t.z))
    fail("a singular or non-finite map (" + type + ")");
  return a;
}

// The tree of one grid, read into a SparseVolume.
class TreeReader {
 public:
  TreeReader(Cursor& c, uint32_t compression, Stored stored, Stored full, SparseVolume& out)
      : c_(c), compression_(compression), stored_(stored), full_(full), out_(out) {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    // A leaf costs its values here and its brick later (2 KB + 2.9 KB).
    max_leaves_ = pages > 0 && page > 0 ? size_t(pages) * size_t(page) / 5120 : size_t(1) << 24;
  }

  void topology() {
    if (const int32_t buffers = c_.get<int32_t>("the buffer count"); buffers != 1)
      fail("a tree with " + std::to_string(buffers) + " buffers (1 expected)" + byte_at(c_));
    out_.background = vdb::read_full(c_, full_, "the background");
    const uint32_t tiles = c_.get<uint32_t>("the root's tile count"),
                   children = c_.get<uint32_t>("the root's child count");
    const size_t value = full_ == Stored::kDouble ? 8 : 4;
    if (tiles > c_.left() / (13 + value) || children > c_.left() / 12)
      fail("root counts (" + std::to_string(tiles) + " tiles, " + std::to_string(children) +
           " children) that the file cannot hold" + byte_at(c_));
    for (uint32_t i = 0; i < tiles; ++i) {
      SparseTile t{origin("a root tile", 4096), 4096, 0.0f};
      t.value = vdb::read_full(c_, full_, "a root tile");
      c_.get<uint8_t>("a root tile");  // active or not: either way the value counts
      if (t.value != out_.background) out_.tiles.push_back(t);
    }
    Index3 last{};
    for (uint32_t i = 0; i < children; ++i) {
      const Index3 o = origin("a root child", 4096);
      if (i > 0 && !(last < o))
        fail("root children out of order or repeated" + byte_at(c_));  // OpenVDB's map order
      last = o;
      internal(5, o);
    }
  }

  // The leaves' values, in the order of their topology.
  void buffers() {
    for (SparseLeaf& leaf : out_.leaves) {
      const Mask mask = vdb::read_mask(c_, 512, "a leaf's value mask");
      vdb::read_values(c_, compression_, stored_, full_, out_.background, mask, 512, leaf.v.data());
    }
  }

 private:
  Index3 origin(const char* what, int align) {
    Index3 o;
    std::memcpy(o.data(), c_.take(12, what), 12);
    for (int v : o)
      if (v % align != 0)
        fail(std::string(what) + " at an origin not a multiple of " + std::to_string(align) +
             byte_at(c_));
    return o;
  }

  // An internal node of 2^(3 log2) entries (5: children of 4096 voxels' side; 4: of 128).
  void internal(int log2, const Index3& o) {
    const size_t n = size_t(1) << (3 * log2);
    const int dim = 1 << log2, child_shift = log2 == 5 ? 7 : 3;
    const Mask child = vdb::read_mask(c_, n, "a child mask"),
               value = vdb::read_mask(c_, n, "a value mask");
    std::vector<float> values(n);
    vdb::read_values(c_, compression_, stored_, full_, out_.background, value, n, values.data());
    const auto at = [&](size_t i) {
      return Index3{o[0] + (int(i >> (2 * log2)) << child_shift),
                    o[1] + (int((i >> log2) & size_t(dim - 1)) << child_shift),
                    o[2] + (int(i & size_t(dim - 1)) << child_shift)};
    };
    for (size_t i = 0; i < n; ++i)
      if (!child.on(i) && values[i] != out_.background)
        out_.tiles.push_back(SparseTile{at(i), 1 << child_shift, values[i]});
    for (size_t i = 0; i < n; ++i) {
      if (!child.on(i)) continue;
      if (log2 == 5) {
        internal(4, at(i));
        continue;
      }
      vdb::read_mask(c_, 512, "a leaf's value mask");  // the buffers carry it again
      if (out_.leaves.size() >= max_leaves_)
        fail("more than " + std::to_string(max_leaves_) +
             " leaves, more than this machine's memory holds");
      out_.leaves.emplace_back().origin = at(i);
    }
  }

  Cursor& c_;
  uint32_t compression_;
  Stored stored_, full_;
  SparseVolume& out_;
  size_t max_leaves_;
};

VdbVolume decode(const uint8_t* data, size_t size, const std::string& wanted, uint64_t max_brick_bytes) {
  Cursor c(data, size);
  if (size < 8 || c.get<int64_t>("the magic number") != kMagic)
    fail("not an OpenVDB file (no VDB magic number)");
  const uint32_t version = c.get<uint32_t>("the file version");
  if (version < kFirstVersion)
    fail("file version " + std::to_string(version) +
         " (OpenVDB before 3.0) is not read: save it again with a newer OpenVDB");
  c.take(8, "the library version");
  if (c.get<uint8_t>("the grid offsets flag") == 0)
    fail("written as a stream without grid offsets (not read)");
  c.take(36, "the file's UUID");
  read_metadata(c, nullptr);
  const int32_t count = c.get<int32_t>("the grid count");
  if (count < 0 || size_t(count) > c.left() / 36)
    fail("a grid count of " + std::to_string(count) + " that the file cannot hold");
  std::vector<Descriptor> grids;
  for (int32_t i = 0; i < count; ++i) {
    Descriptor d;
    d.name = c.string("a grid name");
    d.type = c.string("a grid type");
    d.parent = c.string("a grid's parent");
    d.grid_pos = c.get<uint64_t>("a grid offset");
    d.block_pos = c.get<uint64_t>("a grid offset");
    d.end_pos = c.get<uint64_t>("a grid offset");
    if (d.grid_pos != c.pos() || d.block_pos < d.grid_pos || d.end_pos < d.block_pos ||
        d.end_pos > size)
      fail("grid '" + plain_name(d.name).substr(0, 60) +
           "' has offsets out of order or past the end" + byte_at(c));
    c.seek(d.end_pos, "the next grid");
    grids.push_back(std::move(d));
  }
  const auto value_type = [](const std::string& type, bool& half) {
    half = type.size() > 10 && type.compare(type.size() - 10, 10, "_HalfFloat") == 0;
    const std::string base = half ? type.substr(0, type.size() - 10) : type;
    return base == "Tree_float_5_4_3" ? 1 : base == "Tree_double_5_4_3" ? 2 : 0;
  };
  std::string listed;
  const Descriptor* chosen = nullptr;
  for (const Descriptor& d : grids) {
    bool half = false;
    listed += (listed.empty() ? "" : ", ") + plain_name(d.name).substr(0, 40) + " (" +
              d.type.substr(0, 40) + ")";
    if (!chosen && (wanted.empty() ? value_type(d.type, half) != 0 : plain_name(d.name) == wanted))
      chosen = &d;
  }
  if (!chosen)
    fail((wanted.empty() ? std::string("no float or double grid")
                         : "no grid named '" + wanted.substr(0, 60) + "'") +
         " (the file holds " + (listed.empty() ? std::string("no grids") : listed) + ")");
  const Descriptor& d = *chosen;
  bool half = false;
  const int type = value_type(d.type, half);
  const std::string name = plain_name(d.name);
  if (type == 0)
    fail("grid '" + name + "' holds " + d.type.substr(0, 60) +
         " (float and double grids are read)");
  if (!d.parent.empty())
    fail("grid '" + name + "' is an instance of '" + plain_name(d.parent) + "' (not read)");

  VdbVolume out;
  out.name = name;
  out.grid_class = "unknown";
  c.seek(d.grid_pos, "the grid");
  const uint32_t compression = c.get<uint32_t>("the grid's compression");
  if (compression & ~uint32_t(vdb::kCompressZip | vdb::kCompressActiveMask | vdb::kCompressBlosc))
    fail("unknown compression flags " + std::to_string(compression) + byte_at(c));
  read_metadata(c, &out.grid_class);
  out.index_to_world = read_map(c);
  const Stored full = type == 2 ? Stored::kDouble : Stored::kFloat;
  SparseVolume sparse;
  TreeReader tree(c, compression, half ? Stored::kHalf : full, full, sparse);
  tree.topology();
  if (c.pos() != d.block_pos)
    fail("the tree's topology ends at byte " + std::to_string(c.pos()) + ", its data starts at " +
         std::to_string(d.block_pos));
  tree.buffers();
  if (c.pos() > d.end_pos)
    fail("the grid's data runs past its end (byte " + std::to_string(d.end_pos) + ")");
  out.leaves = sparse.leaves.size();
  out.tiles = sparse.tiles.size();
  auto bricked = brick_sparse_volume(sparse, "grid '" + name + "'", max_brick_bytes);
  if (!bricked) fail(bricked.error().message);
  out.bricked = std::move(*bricked);
  return out;
}

}  // namespace

Affine VdbVolume::grid_to_world() const {
  Affine a = index_to_world;
  a.t = index_to_world.point(
      Vec3(float(bricked.origin[0]), float(bricked.origin[1]), float(bricked.origin[2])));
  return a;
}

Result<VdbVolume> decode_vdb(const uint8_t* data, size_t size, const std::string& path,
                             const std::string& grid, uint64_t max_brick_bytes) {
  try {
    return decode(data, size, grid, max_brick_bytes);
  } catch (const VdbFailure& f) {
    return Error{one_line(path + ": " + f.what)};
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  }
}

Result<VdbVolume> read_vdb(const std::string& path, const std::string& grid) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  if (st.st_size < 8)
    return Error{path + ": not an OpenVDB file (" + std::to_string(st.st_size) + " bytes)"};
  auto bytes = map_file(path, 0, uint64_t(st.st_size));
  if (!bytes) return bytes.error();
  return decode_vdb((*bytes)->data(), (*bytes)->size(), path, grid);
}

}  // namespace frameless
