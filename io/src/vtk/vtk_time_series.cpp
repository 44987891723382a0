#include "isospring/io/vtk_time_series.hpp"

#include <cstdio>
#include <ostream>
#include <stdexcept>

#include "isospring/io/atomic_file.hpp"
#include "isospring/io/vtk_spring_network.hpp"

namespace isospring::io {
namespace fs = std::filesystem;

void write_pvd(const fs::path& path, const std::vector<PvdEntry>& entries) {
  write_file_atomically(path, [&](std::ostream& out) {
    out.precision(17);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        << "  <Collection>\n";
    for (const PvdEntry& e : entries)
      out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"0\" file=\""
          << e.file.generic_string() << "\"/>\n";
    out << "  </Collection>\n</VTKFile>\n";
  });
}

SpringTimeSeriesWriter::SpringTimeSeriesWriter(fs::path pvd, analysis::SpringNetwork network)
    : pvd_(std::move(pvd)), network_(std::move(network)) {}

void SpringTimeSeriesWriter::add_frame(double time,
                                       const std::vector<Eigen::Vector3d>& displacement,
                                       const std::vector<Eigen::Vector3d>& velocity) {
  if (!entries_.empty() && !(time > entries_.back().time))
    throw std::invalid_argument("SpringTimeSeriesWriter: frame times must increase");
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06zu.vtp", entries_.size());
  const fs::path relative = fs::path(pvd_.stem()) / name;
  std::vector<PointVectors> vectors{{"displacement", displacement}};
  if (!velocity.empty()) vectors.push_back({"velocity", velocity});
  write_spring_network_vtp(pvd_.parent_path() / relative, network_, vectors, displacement);
  entries_.push_back({time, relative});
}

void SpringTimeSeriesWriter::finish() {
  write_pvd(pvd_, entries_);
}

}  // namespace isospring::io
