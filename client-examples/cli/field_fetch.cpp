#include "field_fetch.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <map>
#include <utility>
#include <vector>

#include "io/storage/field_snapshot.h"

namespace lbsolid::cli {
namespace {

// One field being received: its header, its bytes, and which byte ranges arrived.
struct FieldBuffer {
  lbsolid::v1::FieldHeader header;
  std::vector<char> bytes;
  std::vector<std::pair<long long, long long>> ranges;  // (offset, size)
};

[[noreturn]] void bad_stream(const std::string& why) { throw CliError(kExitTransient, "GetField: " + why); }

void check_complete(FieldBuffer& f) {
  std::sort(f.ranges.begin(), f.ranges.end());
  long long covered = 0;
  for (const auto& [offset, size] : f.ranges) {
    if (offset != covered)
      bad_stream(f.header.name() + ": chunks overlap or leave a gap at byte " + std::to_string(covered));
    covered += size;
  }
  if (covered != f.header.total_bytes())
    bad_stream(f.header.name() + ": received " + std::to_string(covered) + " of " +
               std::to_string(f.header.total_bytes()) + " bytes");
}

std::vector<double> to_doubles(const std::vector<char>& bytes) {
  std::vector<double> values(bytes.size() / sizeof(double));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(double));
  if constexpr (std::endian::native != std::endian::little) {
    for (auto& v : values) {  // the wire is little-endian
      auto* b = reinterpret_cast<unsigned char*>(&v);
      std::reverse(b, b + sizeof v);
    }
  }
  return values;
}

long long expected_bytes(const lbsolid::v1::FieldHeader& h) {
  long long values = 1;
  for (auto n : h.shape()) {
    if (n < 0) bad_stream(h.name() + ": negative shape");
    values *= n;
  }
  return values * static_cast<long long>(sizeof(double));
}

double positive_or_one(double spacing) { return spacing > 0 ? spacing : 1.0; }

}  // namespace

FetchedFields fetch_fields(Daemon& daemon, const std::string& session_id) {
  lbsolid::v1::GetFieldRequest request;
  request.set_session_id(session_id);
  request.add_fields("density");
  request.add_fields("velocity");
  grpc::ClientContext context;
  daemon.set_deadline(context);
  auto reader = daemon.stub().GetField(&context, request);

  std::map<std::string, FieldBuffer> fields;
  FieldBuffer* current = nullptr;
  lbsolid::v1::FieldMessage message;
  while (reader->Read(&message)) {
    if (message.has_header()) {
      const auto& h = message.header();
      if (h.dtype() != "float64") bad_stream(h.name() + ": unsupported dtype '" + h.dtype() + "'");
      if (h.total_bytes() != expected_bytes(h))
        bad_stream(h.name() + ": total_bytes " + std::to_string(h.total_bytes()) + " does not match its shape");
      current = &fields[h.name()];
      current->header = h;
      current->bytes.assign(static_cast<std::size_t>(h.total_bytes()), 0);
      current->ranges.clear();
    } else if (message.has_chunk()) {
      if (!current) bad_stream("a chunk before any header");
      const auto& c = message.chunk();
      const long long size = static_cast<long long>(c.data().size());
      if (c.offset() < 0 || c.offset() + size > current->header.total_bytes())
        bad_stream(current->header.name() + ": chunk at offset " + std::to_string(c.offset()) +
                   " lies outside the field");
      std::memcpy(current->bytes.data() + c.offset(), c.data().data(), c.data().size());
      current->ranges.emplace_back(c.offset(), size);
    }
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) throw RpcError("GetField", status);

  for (const char* name : {"density", "velocity"})
    if (!fields.count(name)) bad_stream(std::string("no ") + name + " field in the stream");
  FieldBuffer& density = fields["density"];
  FieldBuffer& velocity = fields["velocity"];
  check_complete(density);
  check_complete(velocity);
  const auto& dh = density.header;
  const auto& vh = velocity.header;
  if (dh.shape_size() != 3 || vh.shape_size() != 4 || vh.shape(3) != 3)
    bad_stream("expected shapes [nz, ny, nx] and [nz, ny, nx, 3]");
  for (int axis = 0; axis < 3; ++axis)
    if (dh.shape(axis) != vh.shape(axis)) bad_stream("density and velocity have different shapes");
  if (dh.step() != vh.step()) bad_stream("density and velocity are of different steps");

  FetchedFields out;
  out.step = static_cast<long>(dh.step());
  out.fields.shape = {static_cast<int>(dh.shape(2)), static_cast<int>(dh.shape(1)), static_cast<int>(dh.shape(0))};
  out.fields.density = to_doubles(density.bytes);
  out.fields.velocity = to_doubles(velocity.bytes);
  out.spacing = {positive_or_one(dh.spacing().x()), positive_or_one(dh.spacing().y()),
                 positive_or_one(dh.spacing().z())};
  return out;
}

void write_field_snapshot(const std::string& h5_path, const FetchedFields& fetched) {
  lbsolid::server::storage::SnapshotGeometry geometry;
  geometry.spacing = fetched.spacing;
  try {
    lbsolid::server::storage::append_field_snapshot(h5_path, fetched.fields, fetched.step, geometry);
  } catch (const std::exception& e) {
    throw CliError(kExitBadInput, e.what());
  }
}

}  // namespace lbsolid::cli
