# A Debian package of what cmake --install installs: cpack -G DEB in the build directory writes
# lbsolid_<version>_<arch>.deb. Its dependencies are Debian's runtime packages: the shared
# libraries the binaries link (gRPC, protobuf, Abseil, HDF5, spdlog, ...) as dpkg-shlibdeps finds
# them, and the Python client's modules as Recommends (the binaries run without them).
# The binaries are built as configured: by default (LBSOLID_NATIVE=OFF) the package runs on any
# x86-64 CPU; with LBSOLID_NATIVE=ON only on CPUs like the build machine's.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME lbsolid)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "The lbsolid developers <lbsolid@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "lattice-Boltzmann solid particles in a lattice-Boltzmann fluid, as a service")
set(CPACK_PACKAGE_DESCRIPTION
    "lbsolidd hosts simulation sessions of the Chopard-Marconi model (deformable LB solids in an LB fluid) over gRPC; the lbsolid CLI submits scenarios and fetches results (HDF5); lbsolid-drag-summary reads a drag run. Also the proto files, example scenarios, the Python client and a systemd unit.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-grpcio, python3-protobuf, python3-numpy, python3-h5py")
include(CPack)
