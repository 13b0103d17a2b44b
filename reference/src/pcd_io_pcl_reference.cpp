// PCL's PCD reader and writer, kept as the reference our own decoder (pcd_io.cpp) is
// tested against: both must read every file identically. Not used on the read path:
// PCL allocates for whatever a header promises before it looks at the body.
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <system_error>

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "annex/reference/pcd_io_pcl_reference.h"

namespace annex {
namespace {

Error file_error(const std::filesystem::path& path, std::string message) {
  return Error{std::move(message), Location{path.string()}};
}

// PCL reports problems by printing; we report them as values, so silence it for the
// duration of one call and restore the caller's level afterwards.
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

}  // namespace

Result<Frame> read_pcd_pcl(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return file_error(path, "no such file");
  pcl::PCLPointCloud2 cloud;
  int status = -1;
  try {
    const QuietPcl quiet;
    pcl::PCDReader reader;
    status = reader.read(path.string(), cloud);
  } catch (const std::exception& e) {
    return file_error(path, std::string("cannot read PCD: ") + e.what());
  }
  if (status < 0) return file_error(path, "cannot read PCD: not a valid PCD file, or truncated");

  const std::uint64_t count = static_cast<std::uint64_t>(cloud.width) * cloud.height;
  if (count == 0) return file_error(path, "the cloud has no points");
  if (cloud.point_step == 0 || cloud.data.size() < count * cloud.point_step)
    return file_error(path, "the point data is shorter than WIDTH x HEIGHT points");
  Result<CoordinateField> fx = coordinate_field(cloud, "x", path);
  if (!fx) return fx.error();
  Result<CoordinateField> fy = coordinate_field(cloud, "y", path);
  if (!fy) return fy.error();
  Result<CoordinateField> fz = coordinate_field(cloud, "z", path);
  if (!fz) return fz.error();
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
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint8_t* p = cloud.data.data() + i * cloud.point_step;
    PointXYZRGB& q = frame.points[i];
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
      q.x = q.y = q.z = std::numeric_limits<float>::quiet_NaN();
    }
  }
  if (finite == 0) return file_error(path, "all points are NaN");
  return frame;
}

Status write_pcd_pcl(const std::filesystem::path& path, const Frame& frame, PcdHeader::Data data) {
  pcl::PointCloud<pcl::PointXYZRGBA> cloud;
  cloud.width = static_cast<std::uint32_t>(frame.height > 0 ? frame.width : frame.points.size());
  cloud.height = static_cast<std::uint32_t>(frame.height > 0 ? frame.height : 1);
  cloud.is_dense = false;
  cloud.points.resize(frame.points.size());
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    const PointXYZRGB& p = frame.points[i];
    pcl::PointXYZRGBA& q = cloud.points[i];
    q.x = p.x, q.y = p.y, q.z = p.z;
    q.r = p.r, q.g = p.g, q.b = p.b, q.a = 255;
  }
  int status = -1;
  try {
    const QuietPcl quiet;
    pcl::PCDWriter writer;
    switch (data) {
      case PcdHeader::Data::ascii: status = writer.writeASCII(path.string(), cloud, 9); break;
      case PcdHeader::Data::binary: status = writer.writeBinary(path.string(), cloud); break;
      case PcdHeader::Data::binary_compressed:
        status = writer.writeBinaryCompressed(path.string(), cloud);
        break;
    }
  } catch (const std::exception& e) {
    return file_error(path, std::string("cannot write PCD: ") + e.what());
  }
  if (status < 0) return file_error(path, "cannot write PCD");
  return Ok{};
}

}  // namespace annex
