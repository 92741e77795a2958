// NRRD reading: the header is parsed field by field into NrrdHeader, then the voxels come from a
// DataSource (the bytes in memory, or a file: the header's own or its "data file").
#include "core/io/volume_nrrd.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <new>
#include <string_view>
#include <vector>

#include "core/io/file_util.h"
#include "core/io/volume_raw.h"

namespace frameless {
namespace {

constexpr size_t kMaxHeaderBytes = 1 << 20;  // a longer header has lost its blank line
constexpr size_t kChunk = 1 << 16;

Error fail_at(const std::string& path, int line, const std::string& field, const std::string& what) {
  return Error{one_line(path + ":" + std::to_string(line) + ": " + field + ": " + what)};
}

// Input quoted in a message, cut short so that a line of garbage stays readable.
std::string quote(std::string_view s) {
  std::string out = "'";  // appended, not "'" + string: GCC 12 warns falsely about that form
  return out.append(s.substr(0, 60)).append(s.size() > 60 ? "...'" : "'");
}

std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Lower case with runs of blanks as one space: "Unsigned  Short" -> "unsigned short".
std::string normalized(std::string_view s) {
  std::string out;
  for (char c : trim_blanks(s)) {
    if (c == ' ' || c == '\t') {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += char(std::tolower(static_cast<unsigned char>(c)));
    }
  }
  return out;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  s = trim_blanks(s);
  while (!s.empty()) {
    const size_t end = std::min(s.find_first_of(" \t"), s.size());
    out.push_back(s.substr(0, end));
    s = trim_blanks(s.substr(end));
  }
  return out;
}

bool parse_int(std::string_view s, int64_t& out) {
  s = trim_blanks(s);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

// A positive, finite number that stays so as a float (a spacing).
bool parse_spacing(std::string_view s, double& out) {
  s = trim_blanks(s);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty() && std::isfinite(out) && float(out) > 0.0f &&
         std::isfinite(float(out));
}

// Three vectors "(a,b,c)"; their lengths are the spacings.
bool parse_space_directions(std::string_view s, Vec3& spacing) {
  int axis = 0;
  for (s = trim_blanks(s); !s.empty(); s = trim_blanks(s), ++axis) {
    const size_t close = s.find(')');
    if (axis == 3 || s.front() != '(' || close == std::string_view::npos) return false;
    std::string_view inner = s.substr(1, close - 1);
    s.remove_prefix(close + 1);
    double sum = 0.0;
    for (int c = 0; c < 3; ++c) {
      const size_t comma = c < 2 ? inner.find(',') : inner.size();
      if (comma == std::string_view::npos) return false;
      const std::string_view num = trim_blanks(inner.substr(0, comma));
      double v = 0.0;
      const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), v);
      if (ec != std::errc() || end != num.data() + num.size() || num.empty() || !std::isfinite(v)) return false;
      sum += v * v;
      inner.remove_prefix(c < 2 ? comma + 1 : comma);
    }
    const float length = float(std::sqrt(sum));
    if (!(length > 0.0f) || !std::isfinite(length)) return false;
    spacing[axis] = length;
  }
  return axis == 3;
}

// Field names as teem spells them (old spellings mapped), split into those read here and those
// that only describe the data.
std::string canonical_field(std::string name) {
  static const std::map<std::string, std::string> kAliases = {
      {"datafile", "data file"}, {"byteskip", "byte skip"},       {"lineskip", "line skip"},
      {"oldmin", "old min"},     {"oldmax", "old max"},           {"axismins", "axis mins"},
      {"axismaxs", "axis maxs"}, {"sampleunits", "sample units"}, {"blocksize", "block size"},
      {"centerings", "centers"}};
  const auto a = kAliases.find(name);
  return a == kAliases.end() ? name : a->second;
}
bool is_field_read_here(const std::string& name) {
  static const char* const kNames[] = {"type",     "dimension",        "sizes",     "encoding",  "endian",
                                       "spacings", "space directions", "data file", "byte skip", "line skip"};
  for (const char* n : kNames)
    if (name == n) return true;
  return false;
}
bool is_descriptive_field(const std::string& name) {
  static const char* const kNames[] = {
      "content",         "min",          "max",         "old min",           "old max",     "space",
      "space dimension", "space origin", "space units", "measurement frame", "kinds",       "centers",
      "labels",          "units",        "axis mins",   "axis maxs",         "thicknesses", "sample units",
      "number",          "block size"};
  for (const char* n : kNames)
    if (name == n) return true;
  return false;
}

struct NrrdHeader {
  VoxelType type = VoxelType::kUint8;
  int64_t sizes[3] = {0, 0, 0};
  bool gzip = false;
  bool big_endian = false;
  Vec3 spacing{1.0f};
  std::string data_file;
  int64_t byte_skip = 0, line_skip = 0;
  bool ended = false;                // a blank line closed the header
  size_t data_start = 0;             // attached data: the byte after the blank line
  std::map<std::string, int> lines;  // each field seen -> its header line

  int line(const char* field) const {
    const auto f = lines.find(field);
    return f == lines.end() ? 0 : f->second;
  }
  uint64_t data_bytes() const {
    return uint64_t(sizes[0]) * uint64_t(sizes[1]) * uint64_t(sizes[2]) * voxel_bytes(type);
  }
  std::string dims() const {
    return std::to_string(sizes[0]) + "x" + std::to_string(sizes[1]) + "x" + std::to_string(sizes[2]) + " " +
           voxel_type_name(type);
  }
};

// Reads one field's value into `h`: "" or what is wrong with it.
std::string read_field(NrrdHeader& h, const std::string& field, std::string_view value) {
  if (field == "type") {
    const std::string t = normalized(value);
    if (t == "uchar" || t == "unsigned char" || t == "uint8" || t == "uint8_t")
      h.type = VoxelType::kUint8;
    else if (t == "ushort" || t == "unsigned short" || t == "uint16" || t == "uint16_t" || t == "unsigned short int")
      h.type = VoxelType::kUint16;
    else if (t == "float")
      h.type = VoxelType::kFloat32;
    else
      return "unsupported type " + quote(value) + " (uchar, ushort and float are supported)";
  } else if (field == "dimension") {
    int64_t d = 0;
    if (!parse_int(value, d)) return "not an integer: " + quote(value);
    if (d != 3) return "must be 3 (a volume), not " + std::to_string(d);
  } else if (field == "sizes") {
    const auto w = words(value);
    bool ok = w.size() == 3;
    for (size_t k = 0; ok && k < 3; ++k) ok = parse_int(w[k], h.sizes[k]) && h.sizes[k] > 0;
    if (!ok) return "expected 3 positive integers, not " + quote(value);
  } else if (field == "encoding") {
    const std::string e = normalized(value);
    if (e == "raw")
      h.gzip = false;
    else if (e == "gzip" || e == "gz")
      h.gzip = true;
    else
      return "unsupported encoding " + quote(value) + " (raw and gzip are supported)";
  } else if (field == "endian") {
    const std::string e = normalized(value);
    if (e != "little" && e != "big") return "expected little or big, not " + quote(value);
    h.big_endian = e == "big";
  } else if (field == "spacings") {
    const auto w = words(value);
    double s[3];
    bool ok = w.size() == 3;
    for (size_t k = 0; ok && k < 3; ++k) ok = parse_spacing(w[k], s[k]);
    if (!ok) return "expected 3 positive numbers, not " + quote(value);
    h.spacing = Vec3(float(s[0]), float(s[1]), float(s[2]));
  } else if (field == "space directions") {
    if (!parse_space_directions(value, h.spacing))
      return "expected 3 vectors (a,b,c) of positive length, not " + quote(value);
  } else if (field == "data file") {
    const std::string_view name = trim_blanks(value);
    const auto w = words(name);
    if (name.empty()) return "no file name";
    if (w[0] == "LIST") return "LIST data files (one file per slice) are not supported";
    if (name.find('%') != std::string_view::npos && w.size() > 1)
      return "format-string data files (one file per slice) are not supported";
    if (name.find('\0') != std::string_view::npos) return "the file name holds a NUL byte";
    h.data_file = std::string(name);
  } else if (field == "byte skip") {
    if (!parse_int(value, h.byte_skip) || h.byte_skip < -1)
      return "expected a non-negative integer or -1, not " + quote(value);
  } else if (field == "line skip") {
    if (!parse_int(value, h.line_skip) || h.line_skip < 0)
      return "expected a non-negative integer, not " + quote(value);
  }
  return "";
}

// The header at the start of `bytes`, checked whole (required fields, conflicts, sizes).
Result<NrrdHeader> parse_header(const std::string& bytes, const std::string& path) {
  NrrdHeader h;
  if (bytes.empty()) return fail_at(path, 1, "magic", "not a NRRD file: it is empty");
  size_t pos = 0;
  for (int line_no = 1; pos < bytes.size(); ++line_no) {
    const size_t newline = bytes.find('\n', pos);
    const size_t end = newline == std::string::npos ? bytes.size() : newline;
    if (end > kMaxHeaderBytes) return file_error(path, "the header is longer than 1 MiB (is its blank line missing?)");
    std::string_view line(bytes.data() + pos, end - pos);
    pos = newline == std::string::npos ? bytes.size() : newline + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line_no == 1) {
      if (line.size() != 8 || line.substr(0, 7) != "NRRD000" || line[7] < '1' || line[7] > '5')
        return fail_at(path, 1, "magic",
                       "not a NRRD file: the first line is " + quote(line) + ", not NRRD0001..NRRD0005");
      continue;
    }
    if (line.empty()) {
      h.ended = true;
      h.data_start = pos;
      break;
    }
    if (line.front() == '#') continue;
    const size_t colon = line.find(": "), key_value = line.find(":=");
    if (key_value != std::string_view::npos && key_value < colon) continue;  // "key:=value": ours to ignore
    if (colon == std::string_view::npos && line.back() != ':')
      return fail_at(path, line_no, quote(line), "not a 'field: value' line");
    const size_t name_end = colon == std::string_view::npos ? line.size() - 1 : colon;
    const std::string field = canonical_field(normalized(line.substr(0, name_end)));
    const std::string_view value = colon == std::string_view::npos ? std::string_view() : line.substr(colon + 2);
    if (field.empty()) return fail_at(path, line_no, quote(line), "not a 'field: value' line");
    const auto [first, fresh] = h.lines.emplace(field, line_no);
    if (!fresh)
      return fail_at(path, line_no, field, "duplicate field (first on line " + std::to_string(first->second) + ")");
    if (is_descriptive_field(field)) continue;
    if (!is_field_read_here(field)) return fail_at(path, line_no, field, "unknown field");
    if (const std::string problem = read_field(h, field, value); !problem.empty())
      return fail_at(path, line_no, field, problem);
  }
  for (const char* field : {"type", "dimension", "sizes", "encoding"})
    if (!h.line(field)) return file_error(path, std::string(field) + ": missing field");
  if (voxel_bytes(h.type) > 1 && !h.line("endian"))
    return file_error(path, std::string("endian: missing field (") + voxel_type_name(h.type) + " data needs a byte order)");
  if (h.line("spacings") && h.line("space directions")) {
    const bool later = h.line("spacings") > h.line("space directions");
    return fail_at(path, later ? h.line("spacings") : h.line("space directions"),
                   later ? "spacings" : "space directions", "give spacings or space directions, not both");
  }
  if (h.byte_skip == -1 && h.gzip)
    return fail_at(path, h.line("byte skip"), "byte skip", "-1 (data at the end of the file) needs raw encoding");
  if (const std::string p = volume_size_problem(h.sizes[0], h.sizes[1], h.sizes[2], h.type); !p.empty())
    return fail_at(path, h.line("sizes"), "sizes", p);
  if (!h.ended && h.data_file.empty())
    return file_error(path, "the header has no blank line before its data and names no data file");
  return h;
}

// Where the voxels come from: bytes in memory, or a regular file read with pread.
class DataSource {
 public:
  DataSource() = default;
  explicit DataSource(const std::string& bytes) : memory_(&bytes), size_(bytes.size()) {}
  DataSource(const DataSource&) = delete;
  DataSource& operator=(const DataSource&) = delete;
  ~DataSource() {
    if (fd_ >= 0) ::close(fd_);
  }

  // "" or why the file cannot be read (devices and pipes are refused: they have no length).
  std::string open(const std::string& path) {
    path_ = path;
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) return std::string("cannot open: ") + std::strerror(errno);
    struct stat st {};
    if (fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) return "not a regular file";
    size_ = uint64_t(st.st_size);
    return "";
  }
  bool is_file() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }

  // Up to n bytes at `at` (fewer only at the end); -1 on a read error.
  ptrdiff_t read(uint64_t at, void* out, size_t n) const {
    if (at >= size_) return 0;
    n = size_t(std::min<uint64_t>(n, size_ - at));
    if (memory_) {
      std::memcpy(out, memory_->data() + at, n);
      return ptrdiff_t(n);
    }
    size_t done = 0;
    while (done < n) {
      const ssize_t got = ::pread(fd_, static_cast<char*>(out) + done, n - done, off_t(at + done));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) return -1;
      if (got == 0) break;
      done += size_t(got);
    }
    return ptrdiff_t(done);
  }

 private:
  const std::string* memory_ = nullptr;
  int fd_ = -1;
  std::string path_;
  uint64_t size_ = 0;
};

// Moves `at` past `lines` line ends; false when the data ends first.
bool skip_lines(const DataSource& src, uint64_t& at, int64_t lines) {
  std::vector<char> buf(kChunk);
  while (lines > 0) {
    const ptrdiff_t n = src.read(at, buf.data(), buf.size());
    if (n <= 0) return false;
    const char* p = buf.data();
    const char* const end = p + n;
    while (lines > 0 && (p = static_cast<const char*>(std::memchr(p, '\n', size_t(end - p))))) {
      ++p;
      --lines;
    }
    at += lines > 0 ? uint64_t(n) : uint64_t(p - buf.data());
  }
  return true;
}

// Inflates the gzip (or zlib) stream from `at` to the source's end into `out`: `skip` bytes are
// dropped, then exactly `want` kept. `out` grows as data arrives, so a short stream claiming a
// big volume costs little. "" or what is wrong.
std::string inflate_voxels(const DataSource& src, uint64_t at, uint64_t skip, uint64_t want, const std::string& need,
                           std::vector<uint8_t>& out) {
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) return "cannot start zlib";
  struct Ender {
    z_stream* zs;
    ~Ender() { inflateEnd(zs); }
  } ender{&zs};
  std::vector<uint8_t> in(kChunk), scratch(kChunk);
  uint64_t skipped = 0, kept = 0;
  for (;;) {
    if (zs.avail_in == 0) {
      const ptrdiff_t n = src.read(at, in.data(), in.size());
      if (n < 0) return std::string("read error: ") + std::strerror(errno);
      if (n == 0) return "gzip data is truncated";
      at += uint64_t(n);
      zs.next_in = in.data();
      zs.avail_in = uInt(n);
    }
    uint8_t* target;
    if (skipped < skip) {
      target = scratch.data();
      zs.avail_out = uInt(std::min<uint64_t>(scratch.size(), skip - skipped));
    } else if (kept < want) {
      if (out.size() == kept) {
        const uint64_t grown = std::min<uint64_t>(want, std::max<uint64_t>(2 * out.size(), 1 << 20));
        out.reserve(size_t(grown));
        out.resize(size_t(grown));
      }
      target = out.data() + kept;
      zs.avail_out = uInt(std::min<uint64_t>(out.size() - kept, 1u << 30));
    } else {
      target = scratch.data();  // anything arriving here is more than the sizes say
      zs.avail_out = uInt(scratch.size());
    }
    zs.next_out = target;
    const uInt room = zs.avail_out;
    const int ret = inflate(&zs, Z_NO_FLUSH);
    const uint64_t produced = room - zs.avail_out;
    if (skipped < skip)
      skipped += produced;
    else if (kept < want)
      kept += produced;
    else if (produced > 0)
      return "gzip data holds more than the " + std::to_string(skip + want) + " bytes " + need;
    if (ret == Z_STREAM_END) break;
    if (ret == Z_NEED_DICT) return "gzip data is corrupt: it needs a preset dictionary";
    if (ret == Z_DATA_ERROR) return std::string("gzip data is corrupt: ") + (zs.msg ? zs.msg : "invalid data");
    if (ret == Z_MEM_ERROR) return "out of memory inflating gzip data";
    if (ret != Z_OK && ret != Z_BUF_ERROR)
      return "gzip data cannot be inflated (zlib error " + std::to_string(ret) + ")";
  }
  if (skipped + kept < skip + want)
    return "gzip data holds " + std::to_string(skipped + kept) + " bytes, not the " + std::to_string(skip + want) +
           " bytes " + need;
  const uint64_t left = zs.avail_in + (src.size() - std::min(at, src.size()));
  if (left > 0) return std::to_string(left) + " bytes follow the end of the gzip data";
  out.resize(size_t(kept));
  return "";
}

// The voxels the header describes, from `src` (starting at `start`); `what` names the data in
// errors ("FILE" or "FILE: data file 'D'").
Result<std::shared_ptr<const VolumeGrid>> load_voxels(const NrrdHeader& h, const DataSource& src, uint64_t start,
                                                      const std::string& path, const std::string& what) {
  if (!skip_lines(src, start, h.line_skip))
    return fail_at(path, h.line("line skip"), "line skip", "the data ends before line " + std::to_string(h.line_skip));
  const uint64_t want = h.data_bytes();
  const bool swap = voxels_need_swap(h.type, h.big_endian);
  std::vector<uint8_t> voxels;
  try {
    if (h.gzip) {
      const std::string need = (h.byte_skip ? "byte skip + " : "") + std::string("sizes ") + h.dims() + " need";
      if (const std::string p = inflate_voxels(src, start, uint64_t(h.byte_skip), want, need, voxels); !p.empty())
        return file_error(what, p);
    } else {
      const uint64_t have = src.size() > start ? src.size() - start : 0;
      const uint64_t skip = h.byte_skip == -1 ? (have >= want ? have - want : 0) : uint64_t(h.byte_skip);
      if (skip > have || have - skip != want)
        return file_error(what, "sizes " + h.dims() + " need " + std::to_string(want) + " bytes of data, the data holds " +
                              (skip > have ? "none after its byte skip" : std::to_string(have - skip)));
      // Mapped voxels must lie aligned for their type (the grid reads them as such): else a copy.
      if (src.is_file() && !swap && (start + skip) % voxel_bytes(h.type) == 0) {
        auto mapped = map_file(src.path(), start + skip, want);
        if (!mapped) return file_error(path, mapped.error().message);
        return one_line(make_volume_grid(int(h.sizes[0]), int(h.sizes[1]), int(h.sizes[2]), h.type, h.spacing,
                                         std::move(*mapped), path));
      }
      voxels.resize(size_t(want));  // no more than the source holds: its length was checked
      errno = 0;
      if (src.read(start + skip, voxels.data(), voxels.size()) != ptrdiff_t(want))
        return file_error(what, errno ? std::string("read error: ") + std::strerror(errno) : "the data ended early");
    }
  } catch (const std::bad_alloc&) {
    return file_error(what, "out of memory for " + std::to_string(want) + " bytes of voxels");
  }
  if (swap) swap_voxel_bytes(voxels, h.type);
  return one_line(make_volume_grid(int(h.sizes[0]), int(h.sizes[1]), int(h.sizes[2]), h.type, h.spacing,
                                   owned_storage(std::move(voxels)), path));
}

// The voxels of a parsed header: from its data file, else from `attached` (the header's source).
Result<std::shared_ptr<const VolumeGrid>> load_data(const NrrdHeader& h, const DataSource& attached,
                                                    const std::string& path, const std::string& base_dir) {
  if (h.data_file.empty()) return load_voxels(h, attached, h.data_start, path, path);
  const std::string file = h.data_file.front() == '/' || base_dir.empty() ? h.data_file : base_dir + "/" + h.data_file;
  DataSource detached;
  if (const std::string p = detached.open(file); !p.empty())
    return fail_at(path, h.line("data file"), "data file", quote(file) + ": " + p);
  return load_voxels(h, detached, 0, path, path + ": data file " + quote(file));
}

}  // namespace

Result<std::shared_ptr<const VolumeGrid>> decode_nrrd(const std::string& bytes, const std::string& path,
                                                      const std::string& base_dir) {
  auto header = parse_header(bytes, path);
  if (!header) return header.error();
  const DataSource attached(bytes);
  return load_data(*header, attached, path, base_dir);
}

Result<std::shared_ptr<const VolumeGrid>> read_nrrd(const std::string& path) {
  DataSource file;
  if (const std::string p = file.open(path); !p.empty()) return file_error(path, p);
  // Only the header is read here: the data may be gigabytes, mapped or streamed later.
  std::string header_bytes;
  std::vector<char> buf(kChunk);
  while (header_bytes.size() <= kMaxHeaderBytes) {
    const ptrdiff_t n = file.read(header_bytes.size(), buf.data(), buf.size());
    if (n < 0) return file_error(path, std::string("read error: ") + std::strerror(errno));
    if (n == 0) break;
    const size_t from = header_bytes.size() < 2 ? 0 : header_bytes.size() - 2;
    header_bytes.append(buf.data(), size_t(n));
    if (header_bytes.compare(0, 4, "NRRD", 0, std::min<size_t>(4, header_bytes.size())) != 0) break;
    if (header_bytes.find("\n\n", from) != std::string::npos || header_bytes.find("\n\r\n", from) != std::string::npos)
      break;
  }
  auto header = parse_header(header_bytes, path);
  if (!header) return header.error();
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return load_data(*header, file, path, dir.empty() ? "." : dir);
}

}  // namespace frameless
