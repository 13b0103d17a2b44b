// PCD reading through PCL's io (it knows every PCD variant, binary_compressed
// included); the blob is converted to our Frame here so no other file needs PCL's
// point types. Writing is ours: one fixed layout, no PCL needed.
#include "annex/runtime/pcd_io.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <system_error>

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include "annex/formats/file_io.h"

namespace annex {
namespace {

static_assert(std::endian::native == std::endian::little,
              "PCD binary data is little-endian; add byte swapping for this platform");

Error file_error(const std::filesystem::path& path, std::string message) {
  return Error{std::move(message), Location{path.string()}};
}

// PCL reports problems by printing; we report them as values, so silence it for the
// duration of one read and restore the caller's level afterwards.
class QuietPcl {
 public:
  QuietPcl() : saved_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(saved_); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

 private:
  pcl::console::VERBOSITY_LEVEL saved_;
};

const pcl::PCLPointField* find_field(const pcl::PCLPointCloud2& cloud, const char* name) {
  for (const pcl::PCLPointField& f : cloud.fields)
    if (f.name == name) return &f;
  return nullptr;
}

int datatype_size(std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
    case pcl::PCLPointField::UINT8: return 1;
    case pcl::PCLPointField::INT16:
    case pcl::PCLPointField::UINT16: return 2;
    case pcl::PCLPointField::INT32:
    case pcl::PCLPointField::UINT32:
    case pcl::PCLPointField::FLOAT32: return 4;
    case pcl::PCLPointField::FLOAT64: return 8;
    default: return 0;
  }
}

// Reads one coordinate field as float, whatever floating type the file used.
struct CoordinateField {
  std::uint32_t offset = 0;
  bool is_double = false;
  float read(const std::uint8_t* point) const {
    if (is_double) {
      double v;
      std::memcpy(&v, point + offset, sizeof v);
      return static_cast<float>(v);
    }
    float v;
    std::memcpy(&v, point + offset, sizeof v);
    return v;
  }
};

Result<CoordinateField> coordinate_field(const pcl::PCLPointCloud2& cloud, const char* name,
                                         const std::filesystem::path& path) {
  const pcl::PCLPointField* f = find_field(cloud, name);
  if (!f) return file_error(path, std::string("missing field '") + name + "' (need x y z)");
  if (f->datatype != pcl::PCLPointField::FLOAT32 && f->datatype != pcl::PCLPointField::FLOAT64)
    return file_error(path, std::string("field '") + name + "' is not a float type");
  const int size = datatype_size(f->datatype);
  if (static_cast<std::uint64_t>(f->offset) + size > cloud.point_step)
    return file_error(path, std::string("field '") + name + "' lies outside the point record");
  return CoordinateField{f->offset, f->datatype == pcl::PCLPointField::FLOAT64};
}

// Largest header we look for the DATA line in.
constexpr std::size_t kMaxHeaderBytes = 64 * 1024;
constexpr std::uint64_t kMaxPoints = std::uint64_t{1} << 26;

struct Token {
  std::string_view text;
  int column = 0;  // 1-based
};

std::vector<Token> split_line(std::string_view line) {
  std::vector<Token> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

std::optional<std::uint64_t> parse_whole(std::string_view s) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

Result<PcdHeader> parse_pcd_header(std::string_view text, std::string_view origin) {
  PcdHeader h;
  bool has_fields = false, has_size = false, has_type = false, has_count = false;
  bool has_width = false, has_points = false;
  int line_no = 0;
  std::size_t pos = 0;
  auto fail = [&](int column, std::string message) {
    return Error{std::move(message), Location{std::string(origin), line_no, column}};
  };
  while (pos < text.size()) {
    ++line_no;
    const std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos)
      return fail(1, "the header ends before its DATA line (not a PCD file, or truncated)");
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::vector<Token> tok = split_line(line);
    if (tok.empty() || tok[0].text[0] == '#') continue;
    const std::string_view key = tok[0].text;
    const std::size_t nvalues = tok.size() - 1;
    auto need_values = [&]() -> std::optional<Error> {
      if (nvalues == 0) return fail(tok[0].column + static_cast<int>(key.size()),
                                    "expected values after '" + std::string(key) + "'");
      return std::nullopt;
    };
    auto per_field = [&](std::string_view what) -> std::optional<Error> {
      if (!has_fields) return fail(tok[0].column, std::string(what) + " before FIELDS");
      if (nvalues != h.fields.size())
        return fail(tok[0].column, std::string(what) + " lists " + std::to_string(nvalues) +
                                       " values for " + std::to_string(h.fields.size()) + " fields");
      return std::nullopt;
    };
    auto whole = [&](const Token& t, std::uint64_t max) -> Result<std::uint64_t> {
      const auto v = parse_whole(t.text);
      if (!v || *v > max)
        return fail(t.column, "expected a whole number up to " + std::to_string(max) + ", got '" +
                                  std::string(t.text) + "'");
      return *v;
    };
    if (key == "VERSION" || key == "VIEWPOINT") {
      continue;
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (auto e = need_values()) return *e;
      if (nvalues > 256) return fail(tok[0].column, "more than 256 fields");
      for (std::size_t i = 1; i < tok.size(); ++i) h.fields.emplace_back(tok[i].text);
      has_fields = true;
    } else if (key == "SIZE") {
      if (auto e = per_field("SIZE")) return *e;
      for (std::size_t i = 1; i < tok.size(); ++i) {
        const auto v = parse_whole(tok[i].text);
        if (!v || (*v != 1 && *v != 2 && *v != 4 && *v != 8))
          return fail(tok[i].column, "SIZE must be 1, 2, 4 or 8, got '" + std::string(tok[i].text) + "'");
        h.sizes.push_back(static_cast<int>(*v));
      }
      has_size = true;
    } else if (key == "TYPE") {
      if (auto e = per_field("TYPE")) return *e;
      for (std::size_t i = 1; i < tok.size(); ++i) {
        if (tok[i].text.size() != 1 || std::string_view("IUF").find(tok[i].text[0]) == std::string_view::npos)
          return fail(tok[i].column, "TYPE must be I, U or F, got '" + std::string(tok[i].text) + "'");
        h.types.push_back(tok[i].text[0]);
      }
      has_type = true;
    } else if (key == "COUNT") {
      if (auto e = per_field("COUNT")) return *e;
      for (std::size_t i = 1; i < tok.size(); ++i) {
        Result<std::uint64_t> v = whole(tok[i], 100000);
        if (!v) return v.error();
        if (*v == 0) return fail(tok[i].column, "COUNT must be at least 1");
        h.counts.push_back(static_cast<int>(*v));
      }
      has_count = true;
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      if (auto e = need_values()) return *e;
      if (nvalues != 1) return fail(tok[2].column, "expected one number after " + std::string(key));
      Result<std::uint64_t> v = whole(tok[1], kMaxPoints);
      if (!v) return v.error();
      if (key == "WIDTH") h.width = *v, has_width = true;
      if (key == "HEIGHT") h.height = *v;
      if (key == "POINTS") h.points = *v, has_points = true;
    } else if (key == "DATA") {
      if (auto e = need_values()) return *e;
      if (tok[1].text == "ascii") h.data = PcdHeader::Data::ascii;
      else if (tok[1].text == "binary") h.data = PcdHeader::Data::binary;
      else if (tok[1].text == "binary_compressed") h.data = PcdHeader::Data::binary_compressed;
      else return fail(tok[1].column, "DATA must be ascii, binary or binary_compressed, got '" +
                                          std::string(tok[1].text) + "'");
      h.data_offset = pos;
      // The header is complete: check it as a whole.
      if (!has_fields || !has_size || !has_type)
        return fail(1, "the header lacks FIELDS, SIZE or TYPE");
      if (!has_count) h.counts.assign(h.fields.size(), 1);
      for (std::size_t i = 0; i < h.fields.size(); ++i) {
        if (h.types[i] == 'F' && h.sizes[i] != 4 && h.sizes[i] != 8)
          return fail(1, "field '" + h.fields[i] + "' has TYPE F but SIZE " + std::to_string(h.sizes[i]));
        h.point_step += static_cast<std::size_t>(h.sizes[i]) * h.counts[i];
      }
      if (!has_width) return fail(1, "the header lacks WIDTH");
      if (h.width * h.height > kMaxPoints) return fail(1, "WIDTH x HEIGHT is too large");
      if (!has_points) h.points = h.width * h.height;
      if (h.points != h.width * h.height)
        return fail(1, "POINTS " + std::to_string(h.points) + " is not WIDTH x HEIGHT = " +
                           std::to_string(h.width * h.height));
      return h;
    } else {
      return fail(tok[0].column, "unexpected '" + std::string(key).substr(0, 40) +
                                     "' in the header (not a PCD file?)");
    }
  }
  return Error{"the header ends before its DATA line (not a PCD file, or truncated)",
               Location{std::string(origin), line_no + 1, 1}};
}

Result<Frame> read_pcd(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return file_error(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) return file_error(path, "is a directory, not a PCD file");

  // Check the header and the body's size ourselves first: PCL 1.13 crashes on
  // garbage and on empty files, and trusts the sizes it reads.
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) return file_error(path, "cannot read: " + ec.message());
  std::string prefix(static_cast<std::size_t>(std::min<std::uint64_t>(file_size, kMaxHeaderBytes)), '\0');
  {
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(prefix.data(), static_cast<std::streamsize>(prefix.size())))
      return file_error(path, "cannot read the file");
  }
  Result<PcdHeader> header = parse_pcd_header(prefix, path.string());
  if (!header) return header.error();
  if (header->points == 0) return file_error(path, "the cloud has no points");
  const std::uint64_t body = file_size - header->data_offset;
  const std::uint64_t expected = header->points * header->point_step;
  if (header->data == PcdHeader::Data::binary && body < expected)
    return file_error(path, "truncated: the body holds " + std::to_string(body) + " of " +
                                std::to_string(expected) + " bytes");
  if (header->data == PcdHeader::Data::binary_compressed) {
    if (body < 8) return file_error(path, "truncated: no compressed block after the header");
    std::uint32_t sizes[2];  // compressed, uncompressed
    if (header->data_offset + 8 <= prefix.size()) {
      std::memcpy(sizes, prefix.data() + header->data_offset, 8);
    } else {
      std::ifstream in(path, std::ios::binary);
      in.seekg(static_cast<std::streamoff>(header->data_offset));
      if (!in.read(reinterpret_cast<char*>(sizes), 8)) return file_error(path, "cannot read the file");
    }
    if (sizes[0] == 0 || sizes[0] > body - 8)
      return file_error(path, "truncated or corrupt: the compressed block claims " +
                                  std::to_string(sizes[0]) + " bytes, " + std::to_string(body - 8) +
                                  " remain");
    if (sizes[1] != expected)
      return file_error(path, "corrupt: the compressed block unpacks to " + std::to_string(sizes[1]) +
                                  " bytes, not POINTS x point size = " + std::to_string(expected));
  }

  pcl::PCLPointCloud2 cloud;
  int status = -1;
  try {
    const QuietPcl quiet;
    pcl::PCDReader reader;
    status = reader.read(path.string(), cloud);
  } catch (const std::exception& e) {
    // PCL throws on some malformed headers (pcl::IOException, std::bad_alloc).
    return file_error(path, std::string("cannot read PCD: ") + e.what());
  }
  if (status < 0) return file_error(path, "cannot read PCD: not a valid PCD file, or truncated");

  const std::uint64_t count = static_cast<std::uint64_t>(cloud.width) * cloud.height;
  if (count == 0) return file_error(path, "the cloud has no points");
  if (count > (1u << 26)) return file_error(path, "the cloud has too many points");
  if (cloud.point_step == 0 || cloud.data.size() < count * cloud.point_step)
    return file_error(path, "the point data is shorter than WIDTH x HEIGHT points");

  Result<CoordinateField> fx = coordinate_field(cloud, "x", path);
  if (!fx) return fx.error();
  Result<CoordinateField> fy = coordinate_field(cloud, "y", path);
  if (!fy) return fy.error();
  Result<CoordinateField> fz = coordinate_field(cloud, "z", path);
  if (!fz) return fz.error();

  // Packed colour: "rgba" (uint32) or "rgb" (float or uint32); bytes b, g, r, a.
  std::optional<std::uint32_t> colour_offset;
  for (const char* name : {"rgba", "rgb"}) {
    const pcl::PCLPointField* f = find_field(cloud, name);
    if (f && datatype_size(f->datatype) == 4 &&
        static_cast<std::uint64_t>(f->offset) + 4 <= cloud.point_step) {
      colour_offset = f->offset;
      break;
    }
  }

  Frame frame;
  frame.width = static_cast<int>(cloud.width);
  frame.height = static_cast<int>(cloud.height);
  frame.points.resize(count);
  std::uint64_t finite = 0;
  const std::uint8_t* data = cloud.data.data();
  // Organized files store rows of row_step bytes; trust it only when it is consistent.
  const std::uint64_t row_step =
      cloud.row_step >= static_cast<std::uint64_t>(cloud.width) * cloud.point_step &&
              static_cast<std::uint64_t>(cloud.row_step) * cloud.height <= cloud.data.size()
          ? cloud.row_step
          : static_cast<std::uint64_t>(cloud.width) * cloud.point_step;
  for (std::uint32_t row = 0; row < cloud.height; ++row) {
    for (std::uint32_t col = 0; col < cloud.width; ++col) {
      const std::uint8_t* p = data + row * row_step + col * cloud.point_step;
      PointXYZRGB& q = frame.points[static_cast<std::size_t>(row) * cloud.width + col];
      q.x = fx->read(p);
      q.y = fy->read(p);
      q.z = fz->read(p);
      if (colour_offset) {
        q.b = p[*colour_offset];
        q.g = p[*colour_offset + 1];
        q.r = p[*colour_offset + 2];
      } else {
        q.r = q.g = q.b = 128;
      }
      if (std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) {
        ++finite;
      } else {
        // One convention downstream: an invalid pixel has all three coordinates NaN.
        q.x = q.y = q.z = std::numeric_limits<float>::quiet_NaN();
      }
    }
  }
  if (finite == 0) return file_error(path, "all points are NaN");
  return frame;
}

std::string pcd_bytes(const Frame& frame) {
  const std::size_t count = frame.points.size();
  const int width = frame.height > 0 ? frame.width : static_cast<int>(count);
  const int height = frame.height > 0 ? frame.height : 1;
  std::string out =
      "# .PCD v0.7 - Point Cloud Data file format\n"
      "VERSION 0.7\n"
      "FIELDS x y z rgba\n"
      "SIZE 4 4 4 4\n"
      "TYPE F F F U\n"
      "COUNT 1 1 1 1\n"
      "WIDTH " + std::to_string(width) + "\n"
      "HEIGHT " + std::to_string(height) + "\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS " + std::to_string(count) + "\n"
      "DATA binary\n";
  const std::size_t header = out.size();
  out.resize(header + count * 16);
  char* dst = out.data() + header;
  for (const PointXYZRGB& p : frame.points) {
    const std::uint8_t bgra[4] = {p.b, p.g, p.r, 255};
    std::memcpy(dst, &p.x, 4);
    std::memcpy(dst + 4, &p.y, 4);
    std::memcpy(dst + 8, &p.z, 4);
    std::memcpy(dst + 12, bgra, 4);
    dst += 16;
  }
  return out;
}

Status write_pcd(const std::filesystem::path& path, const Frame& frame) {
  if (frame.height > 0 && static_cast<std::size_t>(frame.width) * frame.height != frame.points.size())
    return file_error(path, "frame size " + std::to_string(frame.width) + "x" +
                                std::to_string(frame.height) + " does not match its " +
                                std::to_string(frame.points.size()) + " points");
  return write_file_atomically(path, pcd_bytes(frame));
}

}  // namespace annex
