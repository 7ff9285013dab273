#pragma once
// Trajectories and observables in the H5MD layout (https://www.nongnu.org/h5md/):
//   /h5md                       attrs version = [1, 1]; groups author (name), creator (name, version)
//   /particles/<body>/box       attrs dimension, boundary ("periodic" | "none" per axis); edges
//   /particles/<body>/position/{step, time, value [frame][particle][dimension]}
//   /particles/<body>/velocity/{step, time, value [frame][particle][dimension]}
//   /observables/<body>/centre_of_mass/{step, time, value [frame][dimension]}
//   /observables/<body>/velocity/{step, time, value [frame][dimension]}     (mass-weighted mean)
//   /observables/<body>/broken_link_count/{step, time, value [frame][1]}
//   /observables/<body>/broken_links/{step, time, value [break][5]}  (once a link broke: one entry
//                               per break at the step that broke it: particle, link, x, y, z)
//   /observables/velocity_profile/{step, time, value [frame][ny]}; /observables/velocity_profile_y [ny]
//   /parameters                 attr scenario (protobuf text of the lbsolid.v1.Scenario)
// step and time are per-series datasets (time = step: lattice time). Series are chunked along an
// unlimited first dimension; appended frames wait in memory until they fill a chunk (about 64 KiB,
// or one frame if larger) and are written then, or by flush() or close(). The file is written as
// <path>.partial-<pid>-<n>, a name of this writer's own, and renamed to <path> by close(), so an
// interrupted writer never leaves a half file under the final name, and two writers of one path
// never share a file.
// With particles, close() then writes <stem>.xdmf beside it (xdmf_text.h: the particles as
// Polyvertex grids for ParaView), through a temporary file and a rename.
#include <array>
#include <memory>
#include <string>
#include <vector>

namespace lbsolid::server::storage {

struct H5mdBox {
  int dimension = 2;
  std::array<double, 3> edges{0, 0, 0};        // box lengths along x, y, z, lattice units
  std::array<bool, 3> periodic{true, true, true};
};

class H5mdWriter {
 public:
  // Throws std::runtime_error naming the path and the cause.
  H5mdWriter(const std::string& path, const std::string& creator_version, const std::string& scenario_text,
             const H5mdBox& box);
  ~H5mdWriter();  // closes and renames if close() was not called (without throwing)
  H5mdWriter(const H5mdWriter&) = delete;
  H5mdWriter& operator=(const H5mdWriter&) = delete;

  // positions, velocities: dimension values per particle (particle-major); the particle count of a
  // body must not change between frames (std::invalid_argument).
  void append_particles(const std::string& body, long step, const std::vector<double>& positions,
                        const std::vector<double>& velocities);
  void append_body(const std::string& body, long step, const std::array<double, 3>& centre_of_mass,
                   const std::array<double, 3>& velocity);
  // Angular momentum, velocity and the torque as 3-vectors (2D: along z), the orientation one
  // value (radians, 2D) and as a quaternion (w, x, y, z).
  void append_rotation(const std::string& body, long step, const std::array<double, 3>& angular_momentum,
                       const std::array<double, 3>& angular_velocity, double orientation,
                       const std::array<double, 4>& orientation_quaternion, const std::array<double, 3>& torque);
  // What the body's anchors absorbed in the step (zero for a body without anchors).
  void append_anchor_force(const std::string& body, long step, const std::array<double, 3>& force);
  // How many of the body's links are broken (zero for a body that cannot break).
  void append_broken_link_count(const std::string& body, long step, long count);
  // One broken link, at the step that broke it: its lower end (an index among the body's
  // particles), the link from there (0 +x, 1 +y, 2 +z) and the midpoint of its ends then.
  void append_broken_link(const std::string& body, long step, int particle, int link,
                          const std::array<double, 3>& position);
  void append_profile(long step, const std::vector<double>& y, const std::vector<double>& u_x);
  void flush();
  void close();  // flushes, closes and renames its .partial-<pid>-<n> file to <path>

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One H5MD time series read back: step[frame], time[frame], and the values of each frame
// flattened (value_shape gives the per-frame shape).
struct H5mdSeries {
  std::vector<long> step;
  std::vector<double> time;
  std::vector<long> value_shape;
  std::vector<double> value;  // frames x product(value_shape)
};

// group: e.g. "/observables/disk/velocity". Throws std::runtime_error naming the path and group.
H5mdSeries read_h5md_series(const std::string& path, const std::string& group);

}  // namespace lbsolid::server::storage
