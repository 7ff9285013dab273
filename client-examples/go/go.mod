// The Go client as a module (import path of the stubs: lbsolid/v1, from the protos' go_package).
// client-examples/go/CMakeLists.txt builds it offline in module mode: go_module_build.cmake
// assembles the module in the build tree (this file, the programs, the stubs generated into v1/)
// with a vendor/ directory made of Debian's Go packages in /usr/share/gocode
// (golang-google-grpc-dev, golang-google-protobuf-dev and what they import), so no module is
// downloaded. Their versions are Debian's, not pinned here: each is the zero pseudo-version, the
// usual mark of a module provided locally. Every module the programs import must be listed.
module lbsolid

go 1.19

require (
	google.golang.org/grpc v0.0.0-00010101000000-000000000000
	google.golang.org/protobuf v0.0.0-00010101000000-000000000000
)

require (
	github.com/golang/protobuf v0.0.0-00010101000000-000000000000 // indirect
	golang.org/x/net v0.0.0-00010101000000-000000000000 // indirect
	golang.org/x/sys v0.0.0-00010101000000-000000000000 // indirect
	golang.org/x/text v0.0.0-00010101000000-000000000000 // indirect
	google.golang.org/genproto v0.0.0-00010101000000-000000000000 // indirect
)
