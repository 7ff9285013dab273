"""Runs a scenario file on lbsolidd and saves what it streamed, with the Python client.

    /usr/bin/python3 client-examples/python/run_scenario.py SCENARIO --steps N [--every K]
        [--address HOST:PORT] [--out DIR] [--checkpoint] [--restore CHECKPOINT_ID]

Creates a session (or restores one from a checkpoint), runs N steps with a progress bar on a
terminal, records particle frames and velocity profiles every K steps, then fetches the density
and velocity fields and writes everything to DIR/run.h5 (h5py): /profiles/{step,y,u_x},
/bodies/<name>/{step,position,velocity,centre_of_mass,mean_velocity,energy}, /fields/<name>.
Without --address it starts a private daemon on a free loopback port.
"""
import argparse
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from lbsolid_client import Client, LocalDaemon, SessionFailed, load_scenario  # noqa: E402


def save(path: Path, record, fields):
    tmp = path.with_suffix(".h5.partial")  # written whole, then renamed: never a half file
    with h5py.File(tmp, "w") as f:
        f.attrs["session_step"] = record.session.step
        if record.profiles:
            g = f.create_group("profiles")
            g["step"] = [p.step for p in record.profiles]
            g["y"] = record.profiles[0].y
            g["u_x"] = np.stack([p.u_x for p in record.profiles])
        if record.particles:
            for name in record.particles[0].bodies:
                g = f.create_group(f"bodies/{name}")
                g["step"], g["position"] = record.trajectory(name)
                g["velocity"] = np.stack([frame.bodies[name].velocity for frame in record.particles])
                for quantity in ("centre_of_mass", "mean_velocity", "energy"):
                    g[quantity] = record.body_series(name, quantity)[1]
        for name, field in fields.items():
            f[f"fields/{name}"] = field.values
            f[f"fields/{name}"].attrs["step"] = field.step
            f[f"fields/{name}"].attrs["spacing"] = field.spacing
    tmp.rename(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario", nargs="?", help="scenario file (text format or JSON)")
    parser.add_argument("--steps", type=int, required=True)
    parser.add_argument("--every", type=int, default=100, help="steps between recorded frames")
    parser.add_argument("--address", help="HOST:PORT of lbsolidd (default: start a private one)")
    parser.add_argument("--out", default="out/python-run")
    parser.add_argument("--checkpoint", action="store_true", help="write a checkpoint at the end")
    parser.add_argument("--restore", help="start from this checkpoint id instead of a scenario")
    args = parser.parse_args()
    if not args.scenario and not args.restore:
        parser.error("give a scenario file or --restore CHECKPOINT_ID")
    if args.restore and not args.address:
        parser.error("--restore needs --address: checkpoints live in the data directory of the daemon that wrote them")

    daemon = None if args.address else LocalDaemon().start()
    client = Client(args.address or daemon.address).wait_ready()
    try:
        session = client.restore(args.restore) if args.restore else client.create(load_scenario(args.scenario))
        for warning in session.snapshot.warnings:
            print(f"warning: {warning}", file=sys.stderr)
        has_fluid = session.snapshot.cells > 0
        record = session.run_and_record(args.steps, profiles_every=args.every if has_fluid else 0,
                                        particles_every=args.every if session.snapshot.particles else 0)
        fields = session.fields() if has_fluid else {}
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        save(out / "run.h5", record, fields)
        print(f"session {session.id}: step {record.session.step}, "
              f"{len(record.profiles)} profiles, {len(record.particles)} particle frames -> {out / 'run.h5'}")
        if args.checkpoint:
            print(f"checkpoint {session.checkpoint().checkpoint_id}")
        return 0
    except SessionFailed as failure:
        print(f"failed: {failure}", file=sys.stderr)
        return 1
    finally:
        client.close()
        if daemon:
            daemon.stop()


if __name__ == "__main__":
    sys.exit(main())
