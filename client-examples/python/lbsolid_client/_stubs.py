"""Finds the Python stubs generated from proto/lbsolid/v1 at build time (never committed).

In a source tree they live in <build>/client-examples/python/generated; LBSOLID_PYTHON_STUBS
overrides the place, and LBSOLID_BUILD_DIR the build directory (default: <repository>/build).
Installed (cmake --install, the Debian package) they are the package lbsolid.v1 beside this one.
"""
import os
import sys
from pathlib import Path

REPOSITORY = Path(__file__).resolve().parents[3]


def build_dir() -> Path:
    return Path(os.environ.get("LBSOLID_BUILD_DIR", REPOSITORY / "build"))


def stub_dir() -> Path:
    explicit = os.environ.get("LBSOLID_PYTHON_STUBS")
    return Path(explicit) if explicit else build_dir() / "client-examples" / "python" / "generated"


def _import_stubs():
    where = stub_dir()
    built = (where / "lbsolid" / "v1" / "simulation_pb2.py").exists()
    if built and str(where) not in sys.path:
        sys.path.insert(0, str(where))
    try:
        from lbsolid.v1 import scenario_pb2, simulation_pb2, simulation_pb2_grpc  # noqa: E402
    except ImportError as error:
        raise ImportError(
            f"lbsolid Python stubs not found in {where} nor installed: build the project first "
            "(deploy/setup.sh, or cmake --build build), install it, or set LBSOLID_PYTHON_STUBS") from error
    return scenario_pb2, simulation_pb2, simulation_pb2_grpc


scenario_pb2, simulation_pb2, simulation_pb2_grpc = _import_stubs()
