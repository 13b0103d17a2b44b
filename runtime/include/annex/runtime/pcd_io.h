#pragma once
// Point Cloud Data (.pcd) files as our Frame: the format of PCL's test data, of the
// synthetic generator's output and of recorded frame directories.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/result.h"
#include "annex/runtime/frame.h"

namespace annex {

// What a PCD header declares, checked for consistency before any body byte is read
// (PCL's own reader crashes on some malformed files, so we never hand it one).
struct PcdHeader {
  enum class Data { ascii, binary, binary_compressed };
  std::vector<std::string> fields;
  std::vector<int> sizes;   // bytes per element: 1, 2, 4 or 8
  std::vector<char> types;  // 'I', 'U' or 'F'
  std::vector<int> counts;  // elements per field
  std::uint64_t width = 0;
  std::uint64_t height = 1;
  std::uint64_t points = 0;
  Data data = Data::ascii;
  std::size_t data_offset = 0;  // first body byte, just after the DATA line
  std::size_t point_step = 0;   // bytes per point in binary layouts
};

// Parses the header at the start of `text` (which may hold more than the header);
// pure, errors as origin:line:col. Only the header's own lines are examined.
Result<PcdHeader> parse_pcd_header(std::string_view text, std::string_view origin);

// Reads any PCD version PCL reads (ascii, binary, binary_compressed) with float
// x y z fields and optional rgb or rgba (no colour: grey). Organized clouds keep
// their width x height; unorganized ones come back with height 1. A missing file,
// missing xyz fields, a corrupt or truncated body, or a cloud whose points are all
// NaN is an Error naming the file, never a crash. Memory and time follow the file's
// real size, whatever its header claims: the file is read whole, then decode_pcd.
Result<Frame> read_pcd(const std::filesystem::path& path);

// read_pcd's decoder on a whole file held in memory; pure (no file IO), so it is
// unit-tested and fuzzed from bytes. Before anything proportional to the header's
// promise is allocated the promise is held against the bytes there are: an ascii
// body needs two bytes per value, a binary one POINTS x point size, a compressed
// block its stated size and at most 88 times that unpacked (LZF's greatest ratio).
// Errors in an ascii body carry origin:line:col.
Result<Frame> decode_pcd(std::string_view bytes, std::string_view origin);

// Writes an organized (or unorganized, height 1) binary PCD with fields x y z rgba,
// the layout of the real scans, atomically (the old file survives a failure).
Status write_pcd(const std::filesystem::path& path, const Frame& frame);

// The bytes write_pcd writes, for tests and for callers that stream frames.
std::string pcd_bytes(const Frame& frame);

}  // namespace annex
