"""Python client for lbsolidd (stubs generated from proto/lbsolid/v1 at build time).

    from lbsolid_client import Client, LocalDaemon, load_scenario
    from lbsolid_client import Cluster  # several daemons
"""
from ._stubs import scenario_pb2, simulation_pb2, simulation_pb2_grpc
from .client import (Body, Client, Field, Particles, Profile, Recording, Session, SessionFailed,
                     load_scenario, particles_from_proto, profile_from_proto, retryable)
from .cluster import Cluster
from .daemon import LocalDaemon
from .errors import (Aborted, AlreadyExists, DataLoss, DeadlineExceeded, FailedPrecondition, Internal,
                     InvalidArgument, LbsolidError, NotFound, OutOfRange, PermissionDenied, ResourceExhausted,
                     Unauthenticated, Unavailable)

__all__ = ["Body", "Client", "Cluster", "Field", "LocalDaemon", "Particles", "Profile", "Recording", "Session",
           "SessionFailed", "load_scenario", "particles_from_proto", "profile_from_proto", "retryable",
           "scenario_pb2", "simulation_pb2", "simulation_pb2_grpc", "LbsolidError", "InvalidArgument", "NotFound",
           "AlreadyExists", "FailedPrecondition", "OutOfRange", "ResourceExhausted", "Unauthenticated",
           "PermissionDenied", "Unavailable", "DeadlineExceeded", "Aborted", "DataLoss", "Internal"]
