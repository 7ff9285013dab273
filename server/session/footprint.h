#pragma once
// What a session will cost the daemon, estimated from its scenario alone, before anything is
// translated, validated or allocated (a 49-byte request once built a 1.27 GB sheet): fluid nodes,
// solid particles and bytes (no threads: every session's fluid steps share the manager's pool).
// Every figure is an upper bound on what scene::build_simulation allocates, saturating instead of overflowing; the admission in
// SessionManager adds them up over the daemon's sessions.
#include "lbsolid/v1/scenario.pb.h"

namespace lbsolid::server {

struct Footprint {
  long long cells = 0;
  long long particles = 0;
  long long resident_bytes = 0;  // populations, solid arrays and exchange tables, for its whole life
  // A copy of the state at a time (a save or checkpoint) and one field read (GetField).
  long long transient_bytes = 0;
  long long bytes() const { return resident_bytes + transient_bytes; }
  Footprint& operator+=(const Footprint& other);
  Footprint& operator-=(const Footprint& other);
};

Footprint estimate_footprint(const lbsolid::v1::Scenario& scenario);

}  // namespace lbsolid::server
