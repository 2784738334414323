// Object clouds: one binary PLY per object (PCL) and an OctoMap of all object points.
#include <octomap/OcTree.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <fstream>

#include "base_station/export/exporter.h"

namespace cairn::base {
namespace {

/// PCL refuses to write an empty cloud; a valid PLY with zero vertices keeps "one file per object".
bool write_empty_ply(const std::string& path, std::string* error) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\ncomment cairn: object without points\n"
         "element vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  out.flush();
  if (!out) *error = "cannot write";
  return bool(out);
}

}  // namespace

bool write_object_ply(const GlobalObject& object, const std::string& path, std::string* error) {
  if (object.cloud_global.empty()) return write_empty_ply(path, error);
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  cloud.reserve(object.cloud_global.size());
  for (const ColoredPoint& p : object.cloud_global) {
    pcl::PointXYZRGB q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    q.r = p.r;
    q.g = p.g;
    q.b = p.b;
    cloud.push_back(q);
  }
  pcl::PLYWriter writer;  // binary, without PCL's "camera" element so other tools read it cleanly
  if (writer.write(path, cloud, /*binary=*/true, /*use_camera=*/false) < 0) {
    *error = "pcl::PLYWriter::write failed";
    return false;
  }
  return true;
}

bool write_objects_octomap(const std::vector<GlobalObject>& objects, double resolution_m, const std::string& path,
                           std::string* error) {
  octomap::OcTree tree(resolution_m);
  for (const GlobalObject& o : objects) {
    for (const ColoredPoint& p : o.cloud_global) tree.updateNode(octomap::point3d(p.x, p.y, p.z), true);
  }
  tree.updateInnerOccupancy();
  if (!tree.writeBinary(path)) {
    *error = "octomap::OcTree::writeBinary failed";
    return false;
  }
  return true;
}

}  // namespace cairn::base
