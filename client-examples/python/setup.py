"""Builds the client package with its gRPC stubs (pyproject.toml holds the metadata).

The stubs are generated from ../../proto/lbsolid/v1 at build time with Debian's protoc
(protobuf-compiler) and grpc_python_plugin (protobuf-compiler-grpc), the same tools the CMake
build uses, into the build tree, so the wheel carries lbsolid/v1/*_pb2*.py beside lbsolid_client.
"""
import shutil
import subprocess
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

PROTO_ROOT = Path(__file__).resolve().parents[2] / "proto"


class BuildWithStubs(build_py):
    def run(self):
        super().run()
        protoc, plugin = shutil.which("protoc"), shutil.which("grpc_python_plugin")
        if not protoc or not plugin:
            raise SystemExit("lbsolid-client: protoc and grpc_python_plugin are needed to build the stubs "
                             "(apt-get install protobuf-compiler protobuf-compiler-grpc)")
        protos = sorted(str(p) for p in (PROTO_ROOT / "lbsolid" / "v1").glob("*.proto"))
        if not protos:
            raise SystemExit(f"lbsolid-client: no proto files in {PROTO_ROOT / 'lbsolid' / 'v1'}")
        subprocess.run([protoc, f"--proto_path={PROTO_ROOT}", f"--python_out={self.build_lib}",
                        f"--grpc_python_out={self.build_lib}", f"--plugin=protoc-gen-grpc_python={plugin}", *protos],
                       check=True)


setup(cmdclass={"build_py": BuildWithStubs})
