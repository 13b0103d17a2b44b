// PCD reading and writing without PCL: the header is checked, the file's size held
// against the header's promise before anything is allocated for it, then the body
// (ascii, binary, or LZF binary_compressed) decoded straight into our Frame. PCL's
// reader, which allocates for the promise, is kept as the reference in
// reference/src/pcd_io_pcl_reference.cpp.
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

#include "annex/formats/file_io.h"
#include "annex/runtime/params_validation.h"
#include "annex/runtime/target_volume_segmenter.h"

namespace annex {
namespace {

static_assert(std::endian::native == std::endian::little,
              "PCD binary data is little-endian; add byte swapping for this platform");

Error file_error(const std::filesystem::path& path, std::string message) {
  return Error{std::move(message), Location{path.string()}};
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

// What the frame needs from one field: where its first element starts in point 0
// and how far apart consecutive points' elements lie (a point record in binary
// bodies, one element in binary_compressed's field-by-field blocks).
struct FieldView {
  std::size_t index = 0;  // in PcdHeader::fields
  std::size_t base = 0;
  std::size_t stride = 0;
  int size = 0;
  char type = 'F';
};

std::optional<std::size_t> field_index(const PcdHeader& h, std::string_view name) {
  for (std::size_t i = 0; i < h.fields.size(); ++i)
    if (h.fields[i] == name) return i;
  return std::nullopt;
}

// The x, y, z fields (float or double) and the packed colour (rgba or rgb, 4 bytes:
// b, g, r, a), or why the file cannot be a depth frame.
struct FrameFields {
  std::size_t xyz[3] = {0, 0, 0};
  std::optional<std::size_t> colour;
};

Result<FrameFields> frame_fields(const PcdHeader& h, std::string_view origin) {
  FrameFields out;
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const auto i = field_index(h, names[k]);
    if (!i) return Error{std::string("missing field '") + names[k] + "' (need x y z)",
                         Location{std::string(origin)}};
    if (h.types[*i] != 'F')
      return Error{std::string("field '") + names[k] + "' is not a float type",
                   Location{std::string(origin)}};
    out.xyz[k] = *i;
  }
  for (const char* name : {"rgba", "rgb"}) {
    const auto i = field_index(h, name);
    if (i && h.sizes[*i] == 4) {
      out.colour = *i;
      break;
    }
  }
  return out;
}

double load_float(const std::uint8_t* p, int size) {
  if (size == 8) {
    double v;
    std::memcpy(&v, p, 8);
    return v;
  }
  float v;
  std::memcpy(&v, p, 4);
  return v;
}

// Fills one point from its raw values; returns whether it is finite. An invalid
// pixel has all three coordinates NaN, the one convention downstream.
bool finish_point(PointXYZRGB& q, float x, float y, float z, const std::uint8_t* bgra) {
  q.x = x, q.y = y, q.z = z;
  if (bgra) {
    q.b = bgra[0], q.g = bgra[1], q.r = bgra[2];
  } else {
    q.r = q.g = q.b = 128;
  }
  if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) return true;
  q.x = q.y = q.z = std::numeric_limits<float>::quiet_NaN();
  return false;
}

Frame empty_frame(const PcdHeader& h) {
  Frame frame;
  frame.width = static_cast<int>(h.width);
  frame.height = static_cast<int>(h.height);
  frame.points.resize(static_cast<std::size_t>(h.points));
  return frame;
}

// binary and (unpacked) binary_compressed bodies: every field at base + point * stride.
Result<Frame> decode_fixed(const PcdHeader& h, const FrameFields& ff, const std::uint8_t* data,
                           const std::vector<FieldView>& views, std::string_view origin) {
  Frame frame = empty_frame(h);
  std::uint64_t finite = 0;
  const FieldView &vx = views[ff.xyz[0]], &vy = views[ff.xyz[1]], &vz = views[ff.xyz[2]];
  const FieldView* vc = ff.colour ? &views[*ff.colour] : nullptr;
  for (std::size_t p = 0; p < frame.points.size(); ++p) {
    const float x = static_cast<float>(load_float(data + vx.base + p * vx.stride, vx.size));
    const float y = static_cast<float>(load_float(data + vy.base + p * vy.stride, vy.size));
    const float z = static_cast<float>(load_float(data + vz.base + p * vz.stride, vz.size));
    const std::uint8_t* c = vc ? data + vc->base + p * vc->stride : nullptr;
    finite += finish_point(frame.points[p], x, y, z, c) ? 1 : 0;
  }
  if (finite == 0) return Error{"all points are NaN", Location{std::string(origin)}};
  return frame;
}

// LZF (liblzf's format, which PCL writes): a control byte below 32 starts a run of
// ctrl + 1 literal bytes; otherwise its top 3 bits (7: plus the next byte) + 2 are a
// length and the low 5 bits with the next byte an offset back into the output.
// Returns the bytes written, or nullopt when the stream reads or writes out of bounds.
std::optional<std::size_t> lzf_decompress(const std::uint8_t* in, std::size_t in_size,
                                          std::uint8_t* out, std::size_t out_size) {
  std::size_t ip = 0, op = 0;
  while (ip < in_size) {
    const unsigned ctrl = in[ip++];
    if (ctrl < 32) {
      const std::size_t len = ctrl + 1;
      if (len > in_size - ip || len > out_size - op) return std::nullopt;
      std::memcpy(out + op, in + ip, len);
      ip += len, op += len;
      continue;
    }
    std::size_t len = ctrl >> 5;
    if (len == 7) {
      if (ip >= in_size) return std::nullopt;
      len += in[ip++];
    }
    len += 2;
    if (ip >= in_size) return std::nullopt;
    const std::size_t back = ((static_cast<std::size_t>(ctrl & 0x1f) << 8) | in[ip++]) + 1;
    if (back > op || len > out_size - op) return std::nullopt;
    // Byte by byte: the reference may overlap what it writes (a run).
    for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
  }
  return op;
}

// One token of an ascii body, parsed as its field's type; floats keep their bits
// (a packed rgb float), integers their value.
bool parse_ascii_value(std::string_view t, int size, char type, double& as_float,
                       std::uint32_t& as_bits) {
  const char* b = t.data();
  const char* e = t.data() + t.size();
  if (type == 'F') {
    if (t.size() > 1 && t[0] == '+' && t[1] != '-') ++b;  // from_chars takes no '+'

    if (size == 4) {
      float v = 0;
      const auto r = std::from_chars(b, e, v);
      if (r.ec != std::errc() || r.ptr != e) return false;
      as_float = v;
      std::memcpy(&as_bits, &v, 4);
      return true;
    }
    double v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e) return false;
    as_float = v;
    as_bits = 0;
    return true;
  }
  if (type == 'U') {
    std::uint64_t v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e) return false;
    if (size < 8 && v >> (8 * size) != 0) return false;
    as_float = static_cast<double>(v);
    as_bits = static_cast<std::uint32_t>(v);
    return true;
  }
  std::int64_t v = 0;
  const auto r = std::from_chars(b, e, v);
  if (r.ec != std::errc() || r.ptr != e) return false;
  if (size < 8) {
    const std::int64_t lim = std::int64_t{1} << (8 * size - 1);
    if (v < -lim || v >= lim) return false;
  }
  as_float = static_cast<double>(v);
  as_bits = static_cast<std::uint32_t>(v);
  return true;
}

// ascii bodies: one point per non-empty line, one token per field element.
Result<Frame> decode_ascii(const PcdHeader& h, const FrameFields& ff, std::string_view bytes,
                           std::string_view origin, int header_lines) {
  std::size_t elements = 0;
  for (int c : h.counts) elements += static_cast<std::size_t>(c);
  // The first element's token position of each field on a line.
  std::vector<std::size_t> first(h.fields.size());
  for (std::size_t i = 0, at = 0; i < h.fields.size(); at += h.counts[i], ++i) first[i] = at;

  Frame frame = empty_frame(h);
  std::uint64_t finite = 0;
  std::size_t point = 0;
  std::size_t pos = h.data_offset;
  int line_no = header_lines;
  std::vector<Token> tok;
  while (pos < bytes.size()) {
    ++line_no;
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos) eol = bytes.size();
    std::string_view line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    tok = split_line(line);
    if (tok.empty()) continue;
    auto fail = [&](int column, std::string message) {
      return Error{std::move(message), Location{std::string(origin), line_no, column}};
    };
    if (point == frame.points.size())
      return fail(tok[0].column, "more points than POINTS " + std::to_string(h.points));
    if (tok.size() != elements)
      return fail(tok.size() > elements
                      ? tok[elements].column
                      : tok.back().column + static_cast<int>(tok.back().text.size()),
                  "expected " + std::to_string(elements) + " values on a point's line, got " +
                      std::to_string(tok.size()));
    double xyz[3] = {0, 0, 0};
    std::uint8_t bgra[4] = {0, 0, 0, 0};
    for (std::size_t f = 0; f < h.fields.size(); ++f) {
      for (int c = 0; c < h.counts[f]; ++c) {
        const Token& t = tok[first[f] + c];
        double v = 0;
        std::uint32_t bits = 0;
        if (!parse_ascii_value(t.text, h.sizes[f], h.types[f], v, bits))
          return fail(t.column, "field '" + h.fields[f] + "' expects " +
                                    (h.types[f] == 'F' ? "a number" : "a whole number in range") +
                                    ", got '" + std::string(t.text.substr(0, 40)) + "'");
        if (c != 0) continue;
        for (int k = 0; k < 3; ++k)
          if (f == ff.xyz[k]) xyz[k] = v;
        if (ff.colour && f == *ff.colour) std::memcpy(bgra, &bits, 4);
      }
    }
    finite += finish_point(frame.points[point++], static_cast<float>(xyz[0]),
                           static_cast<float>(xyz[1]), static_cast<float>(xyz[2]),
                           ff.colour ? bgra : nullptr)
                  ? 1
                  : 0;
  }
  if (point != frame.points.size())
    return Error{"truncated: the body holds " + std::to_string(point) + " of POINTS " +
                     std::to_string(h.points) + " points",
                 Location{std::string(origin), line_no + 1, 1}};
  if (finite == 0) return Error{"all points are NaN", Location{std::string(origin)}};
  return frame;
}

// Most bytes an LZF stream can unpack to per byte: a back reference of 264 bytes
// in 3 bytes.
constexpr std::uint64_t kLzfMaxExpansion = 88;

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
      // Given twice, a list would no longer match the fields it describes.
      if ((what == "SIZE" && has_size) || (what == "TYPE" && has_type) ||
          (what == "COUNT" && has_count))
        return fail(tok[0].column, std::string(what) + " given twice");
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
      if (has_fields) return fail(tok[0].column, std::string(key) + " given twice");
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

namespace {

Status check_pcd_promise(const PcdHeader& h, std::uint64_t file_size, const std::uint8_t* sizes8,
                         std::string_view origin) {
  auto fail = [&](std::string message) { return Error{std::move(message), Location{std::string(origin)}}; };
  if (h.points == 0) return fail("the cloud has no points");
  const std::uint64_t body = file_size >= h.data_offset ? file_size - h.data_offset : 0;
  const std::uint64_t expected = h.points * h.point_step;
  switch (h.data) {
    case PcdHeader::Data::ascii: {
      // Every element is at least one character and one separator (the last
      // point's newline may be missing).
      std::uint64_t elements = 0;
      for (int c : h.counts) elements += static_cast<std::uint64_t>(c);
      const std::uint64_t least = h.points * elements * 2 - 1;
      if (body < least)
        return fail("truncated or lying header: " + std::to_string(h.points) + " points of " +
                    std::to_string(elements) + " values need at least " + std::to_string(least) +
                    " bytes of ascii body, the file holds " + std::to_string(body));
      return Ok{};
    }
    case PcdHeader::Data::binary:
      if (body < expected)
        return fail("truncated: the body holds " + std::to_string(body) + " of " +
                    std::to_string(expected) + " bytes");
      return Ok{};
    case PcdHeader::Data::binary_compressed: {
      if (body < 8 || !sizes8) return fail("truncated: no compressed block after the header");
      std::uint32_t sizes[2];  // compressed, uncompressed
      std::memcpy(sizes, sizes8, 8);
      if (sizes[0] == 0 || sizes[0] > body - 8)
        return fail("truncated or corrupt: the compressed block claims " +
                    std::to_string(sizes[0]) + " bytes, " + std::to_string(body - 8) + " remain");
      if (sizes[1] != expected)
        return fail("corrupt: the compressed block unpacks to " + std::to_string(sizes[1]) +
                    " bytes, not POINTS x point size = " + std::to_string(expected));
      if (sizes[1] > sizes[0] * kLzfMaxExpansion)
        return fail("corrupt: " + std::to_string(sizes[0]) + " compressed bytes cannot unpack to " +
                    std::to_string(sizes[1]) + " (LZF expands at most " +
                    std::to_string(kLzfMaxExpansion) + " times)");
      return Ok{};
    }
  }
  return Ok{};
}

// A PCD holds points, not the camera: an organized cloud's pixels are back-projected
// through one, recovered here by least squares (estimate_intrinsics); the Kinect's, as
// scaled to the grid, when the points follow no pinhole camera.
void recover_intrinsics(Frame& frame) {
  if (!frame.organized()) return;
  const Result<CameraIntrinsics> k = estimate_intrinsics(frame);
  if (k && validate_intrinsics(*k)) frame.intrinsics = *k;
}

Result<Frame> decode_body(std::string_view bytes, std::string_view origin) {
  Result<PcdHeader> header = parse_pcd_header(bytes.substr(0, kMaxHeaderBytes), origin);
  if (!header) return header.error();
  const PcdHeader& h = *header;
  const std::uint8_t* body = reinterpret_cast<const std::uint8_t*>(bytes.data()) + h.data_offset;
  const bool has_sizes = bytes.size() >= h.data_offset + 8;
  if (Status s = check_pcd_promise(h, bytes.size(), has_sizes ? body : nullptr, origin); !s)
    return s.error();
  Result<FrameFields> ff = frame_fields(h, origin);
  if (!ff) return ff.error();

  if (h.data == PcdHeader::Data::ascii) {
    const int header_lines =
        static_cast<int>(std::count(bytes.begin(), bytes.begin() + h.data_offset, '\n'));
    return decode_ascii(h, *ff, bytes, origin, header_lines);
  }
  std::vector<FieldView> views(h.fields.size());
  std::size_t offset = 0;
  for (std::size_t i = 0; i < h.fields.size(); ++i) {
    const std::size_t element = static_cast<std::size_t>(h.sizes[i]);
    views[i] = FieldView{i, 0, 0, h.sizes[i], h.types[i]};
    if (h.data == PcdHeader::Data::binary) {
      views[i].base = offset;  // within the point record
      views[i].stride = h.point_step;
      offset += element * h.counts[i];
    } else {
      views[i].base = offset;  // field-by-field blocks
      views[i].stride = element * h.counts[i];
      offset += element * h.counts[i] * h.points;
    }
  }
  if (h.data == PcdHeader::Data::binary) return decode_fixed(h, *ff, body, views, origin);

  std::uint32_t sizes[2];
  std::memcpy(sizes, body, 8);
  std::vector<std::uint8_t> unpacked(sizes[1]);
  const std::optional<std::size_t> n = lzf_decompress(body + 8, sizes[0], unpacked.data(), sizes[1]);
  if (!n) return Error{"corrupt: the compressed block does not decode", Location{std::string(origin)}};
  if (*n != sizes[1])
    return Error{"corrupt: the compressed block decodes to " + std::to_string(*n) + " of " +
                     std::to_string(sizes[1]) + " bytes",
                 Location{std::string(origin)}};
  return decode_fixed(h, *ff, unpacked.data(), views, origin);
}

}  // namespace

Result<Frame> decode_pcd(std::string_view bytes, std::string_view origin) {
  Result<Frame> frame = decode_body(bytes, origin);
  if (frame) recover_intrinsics(*frame);
  return frame;
}

Result<Frame> read_pcd(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return file_error(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) return file_error(path, "is a directory, not a PCD file");
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) return file_error(path, "cannot read: " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) return file_error(path, "cannot read the file");

  // The header and the body's first bytes, checked against the file's size before
  // anything proportional to the header's promise is allocated.
  std::string bytes(static_cast<std::size_t>(std::min<std::uint64_t>(file_size, kMaxHeaderBytes)), '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    return file_error(path, "cannot read the file");
  Result<PcdHeader> header = parse_pcd_header(bytes, path.string());
  if (!header) return header.error();
  const bool has_sizes = bytes.size() >= header->data_offset + 8;
  if (Status s = check_pcd_promise(
          *header, file_size,
          has_sizes ? reinterpret_cast<const std::uint8_t*>(bytes.data()) + header->data_offset
                    : nullptr,
          path.string());
      !s)
    return s.error();
  if (file_size > bytes.size()) {
    const std::size_t have = bytes.size();
    bytes.resize(static_cast<std::size_t>(file_size));
    if (!in.read(bytes.data() + have, static_cast<std::streamsize>(file_size - have)))
      return file_error(path, "cannot read the file");
  }
  return decode_pcd(bytes, path.string());
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
