"""Frames read back from a particles.h5 the daemon recorded (H5MD, io/storage/h5md_file.h):
the velocity profile series and each body's particles, mean motion, rotation and broken links."""
import h5py
import numpy as np


def _series(group):
    return np.asarray(group["step"][...], dtype=np.int64), np.asarray(group["value"][...], dtype=np.float64)


def _xyz(values, dimension):
    """[..., dimension] -> [..., 3] with z = 0 in 2D, as the wire carries them."""
    if dimension == 3:
        return values
    pad = np.zeros(values.shape[:-1] + (3 - dimension,))
    return np.concatenate([values, pad], axis=-1)


def recording_from_h5md(path, session, profiles_every=0, particles_every=0, bodies=()):
    """A Recording of the frames at multiples of the intervals asked for (0: none)."""
    from .client import Body, Particles, Profile, Recording  # the types the streams give
    profiles, particles = [], []
    with h5py.File(path, "r") as f:
        if profiles_every and "observables/velocity_profile" in f:
            steps, values = _series(f["observables/velocity_profile"])
            y = np.asarray(f["observables/velocity_profile_y"][...], dtype=np.float64)
            profiles = [Profile(int(s), y, v) for s, v in zip(steps, values) if s % profiles_every == 0]
        if particles_every and "particles" in f:
            names = list(bodies) or sorted(f["particles"].keys())
            frames = {}
            for name in names:
                group = f[f"particles/{name}"]
                dimension = int(group["box"].attrs["dimension"])
                steps, positions = _series(group["position"])
                _, velocities = _series(group["velocity"])
                _, centres = _series(f[f"observables/{name}/centre_of_mass"])
                _, means = _series(f[f"observables/{name}/velocity"])
                rotation = {}  # files from before the rotation observables have none
                for quantity in ("angular_momentum", "angular_velocity", "orientation", "orientation_quaternion",
                                 "torque", "anchor_force"):
                    if f"observables/{name}/{quantity}" in f:
                        rotation[quantity] = _series(f[f"observables/{name}/{quantity}"])[1]
                counts = breaks = None  # files from before fracture have neither; unbroken bodies no breaks
                if f"observables/{name}/broken_link_count" in f:
                    counts = _series(f[f"observables/{name}/broken_link_count"])[1]
                    break_steps, rows = (_series(f[f"observables/{name}/broken_links"])
                                         if f"observables/{name}/broken_links" in f else
                                         (np.zeros(0, dtype=np.int64), np.zeros((0, 5))))
                    breaks = np.column_stack([break_steps, rows]).reshape(-1, 6)
                previous = -1  # as a stream gives them: the breaks since its previous frame
                for k, step in enumerate(steps):
                    if step % particles_every:
                        continue
                    body = frames.setdefault(int(step), {})[name] = Body(
                        name, _xyz(positions[k], dimension), _xyz(velocities[k], dimension),
                        _xyz(centres[k], dimension), _xyz(means[k], dimension), float("nan"), float("nan"),
                        rotation["angular_momentum"][k] if "angular_momentum" in rotation else None,
                        rotation["angular_velocity"][k] if "angular_velocity" in rotation else None,
                        float(rotation["orientation"][k][0]) if "orientation" in rotation else float("nan"),
                        rotation["orientation_quaternion"][k] if "orientation_quaternion" in rotation else None,
                        rotation["torque"][k] if "torque" in rotation else None,
                        rotation["anchor_force"][k] if "anchor_force" in rotation else None)
                    if counts is not None:
                        body.broken_link_count = int(counts[k][0])
                        body.broken_links = breaks[(breaks[:, 0] > previous) & (breaks[:, 0] <= step)]
                    previous = int(step)
            particles = [Particles(step, frames[step]) for step in sorted(frames)]
    return Recording(session, profiles, particles)
