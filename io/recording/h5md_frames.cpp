#include "io/recording/h5md_frames.h"

#include <array>
#include <vector>

namespace lbsolid::server::recording {
namespace {

// The wire carries x, y, z per particle; the H5MD file has `dimension` values per particle.
std::vector<double> per_dimension(const google::protobuf::RepeatedField<double>& xyz, int dimension) {
  if (dimension == 3) return {xyz.begin(), xyz.end()};
  std::vector<double> out;
  out.reserve(xyz.size() / 3 * dimension);
  for (int i = 0; i + 2 < xyz.size(); i += 3)
    for (int axis = 0; axis < dimension; ++axis) out.push_back(xyz[i + axis]);
  return out;
}

std::array<double, 3> array_of(const lbsolid::v1::Vector3& v) { return {v.x(), v.y(), v.z()}; }
std::array<double, 4> array_of(const lbsolid::v1::Quaternion& q) { return {q.w(), q.x(), q.y(), q.z()}; }

}  // namespace

void append_particle_frame(storage::H5mdWriter& writer, const lbsolid::v1::ParticleFrame& frame, int dimension) {
  for (const auto& body : frame.bodies()) {
    writer.append_particles(body.name(), frame.step(), per_dimension(body.position(), dimension),
                            per_dimension(body.velocity(), dimension));
    writer.append_body(body.name(), frame.step(), array_of(body.centre_of_mass()), array_of(body.mean_velocity()));
    writer.append_rotation(body.name(), frame.step(), array_of(body.angular_momentum()),
                           array_of(body.angular_velocity()), body.orientation(), array_of(body.orientation_quaternion()),
                           array_of(body.torque()));
    writer.append_anchor_force(body.name(), frame.step(), array_of(body.anchor_force()));
    writer.append_broken_link_count(body.name(), frame.step(), body.broken_link_count());
    for (const auto& link : body.broken_links())
      writer.append_broken_link(body.name(), link.step(), link.particle(), link.link(), array_of(link.position()));
  }
}

void append_profile_frame(storage::H5mdWriter& writer, const lbsolid::v1::ProfileFrame& frame) {
  writer.append_profile(frame.step(), {frame.y().begin(), frame.y().end()}, {frame.u_x().begin(), frame.u_x().end()});
}

}  // namespace lbsolid::server::recording
