# Run by Debian's pvpython: opens a run's particles.xdmf and fields.xdmf (`lbsolid submit --out DIR`)
# in ParaView and checks that what ParaView reads is what the HDF5 files hold, read independently
# with h5py: the time steps, and at the first two, a middle and the last one every body's points
# and velocities, and the fields' grid, spacing, density and velocity. Doubles come from the same
# datasets on both paths, so they must be equal bit for bit.
#   pvpython paraview_xdmf_check.py DIR
# particles.xdmf is read with ParaView's "XDMF Reader" (Xdmf 2): its Xdmf3 readers do not
# implement the HyperSlab data items that select one frame of an H5MD dataset (ParaView 5.11
# crashes in them). fields.xdmf, plain datasets, is read with all three.
import os
import re
import sys

import h5py
import numpy as np
from paraview import servermanager, simple
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
from vtkmodules.util.numpy_support import vtk_to_numpy

out = sys.argv[1]
checked = []


def fail(message):
    print(f"paraview_xdmf_check {out}: {message}", file=sys.stderr)
    sys.exit(1)


def expect_equal(what, got, want):
    got, want = np.asarray(got), np.asarray(want)
    if got.shape != want.shape:
        fail(f"{what}: ParaView read shape {got.shape}, the HDF5 file holds {want.shape}")
    if not np.array_equal(got, want):
        worst = np.max(np.abs(got.astype(float) - want.astype(float)))
        fail(f"{what}: ParaView read values that differ from the HDF5 file (largest difference {worst})")
    checked.append(what)


def frames_to_check(count):
    return sorted({0, 1, count // 2, count - 1} & set(range(count)))


def blocks_by_name(data):
    """The leaves of a (nested) multiblock dataset by their block names."""
    found = {}
    if data.IsA("vtkMultiBlockDataSet"):
        for b in range(data.GetNumberOfBlocks()):
            child = data.GetBlock(b)
            if child is None:
                continue
            if child.IsA("vtkMultiBlockDataSet"):
                found.update(blocks_by_name(child))
            else:
                # The reader makes grid names unique over the whole file: the body "disk" of the
                # 108th step is "disk[107]".
                name = re.sub(r"\[\d+\]$", "", data.GetMetaData(b).Get(vtkCompositeDataSet.NAME()))
                if name in found:
                    fail(f"two grids named {name} in one time step")
                found[name] = child
    return found


def check_particles():
    path = os.path.join(out, "particles.xdmf")
    with h5py.File(os.path.join(out, "particles.h5"), "r") as h5:
        bodies = sorted(h5["particles"].keys())
        dimension = int(h5[f"particles/{bodies[0]}/box"].attrs["dimension"])
        times = h5[f"particles/{bodies[0]}/position/time"][:]
        reader = simple.XDMFReader(FileNames=[path])
        expect_equal("particles.xdmf time steps", np.array(reader.TimestepValues, dtype=float),
                     times.astype(float))
        for frame in frames_to_check(len(times)):
            reader.UpdatePipeline(float(times[frame]))
            blocks = blocks_by_name(servermanager.Fetch(reader))
            if sorted(blocks) != bodies:
                fail(f"frame {frame}: ParaView read the bodies {sorted(blocks)}, the file holds {bodies}")
            for body in bodies:
                grid = blocks[body]
                position = h5[f"particles/{body}/position/value"][frame]
                velocity = h5[f"particles/{body}/velocity/value"][frame]
                points = vtk_to_numpy(grid.GetPoints().GetData())
                expect_equal(f"{body} points at frame {frame}", points[:, :dimension], position)
                if dimension == 2:
                    expect_equal(f"{body} z at frame {frame}", points[:, 2], np.zeros(len(position)))
                    for axis, name in enumerate(("velocity_x", "velocity_y")):
                        array = vtk_to_numpy(grid.GetPointData().GetArray(name))
                        expect_equal(f"{body} {name} at frame {frame}", array, velocity[:, axis])
                else:
                    array = vtk_to_numpy(grid.GetPointData().GetArray("velocity"))
                    expect_equal(f"{body} velocity at frame {frame}", array, velocity)
                if grid.GetNumberOfCells() != len(position):
                    fail(f"{body}: {grid.GetNumberOfCells()} vertex cells for {len(position)} particles")
        simple.Delete(reader)


def check_fields():
    path = os.path.join(out, "fields.xdmf")
    with h5py.File(os.path.join(out, "fields.h5"), "r") as h5:
        steps = sorted(h5["fields"].keys())
        last = h5[f"fields/{steps[-1]}"]
        density, velocity = last["density"][:], last["velocity"][:]
        nz, ny, nx = density.shape
        for name, make in (("XDMFReader", lambda: simple.XDMFReader(FileNames=[path])),
                           ("Xdmf3ReaderS", lambda: simple.Xdmf3ReaderS(FileName=[path])),
                           ("Xdmf3ReaderT", lambda: simple.Xdmf3ReaderT(FileName=[path]))):
            reader = make()
            expect_equal(f"fields.xdmf time steps ({name})", np.array(reader.TimestepValues, dtype=float).reshape(-1),
                         np.array([float(h5[f"fields/{s}"].attrs["step"]) for s in steps]))
            reader.UpdatePipeline(float(last.attrs["step"]))
            data = servermanager.Fetch(reader)
            grids = list(blocks_by_name(data).values()) if data.IsA("vtkMultiBlockDataSet") else [data]
            if len(grids) != 1 or not grids[0].IsA("vtkImageData"):
                fail(f"{name}: expected one image grid, got {[g.GetClassName() for g in grids]}")
            grid = grids[0]
            expect_equal(f"fields grid dimensions ({name})", grid.GetDimensions(), (nx, ny, nz))
            expect_equal(f"fields grid spacing ({name})", grid.GetSpacing(), last.attrs["spacing"])  # both x, y, z
            expect_equal(f"density ({name})", vtk_to_numpy(grid.GetPointData().GetArray("density")), density.reshape(-1))
            expect_equal(f"velocity ({name})", vtk_to_numpy(grid.GetPointData().GetArray("velocity")),
                         velocity.reshape(-1, 3))
            simple.Delete(reader)


check_particles()
check_fields()
print(f"paraview_xdmf_check {out}: {len(checked)} checks equal to the HDF5 files")
