#!/usr/bin/env python3
"""The cells the chosen sensors observe, as an Open3D point cloud.

Chooses N sensors on the bundled example (or the scene given), then builds a point cloud of the
reference cells' centres coloured by how many chosen sensors see each cell (grey: none, then
green, teal, blue for 1, 2, 3 or more). With Open3D installed (`import open3d` works, e.g.
Debian's python3-open3d) it is an `open3d.geometry.PointCloud`, written with Open3D's writer;
without it the same points and colours are written as an ASCII PLY with NumPy alone, which
Open3D, MeshLab or CloudCompare open.

    PYTHONPATH=build/python python3 examples/python/observed_cloud.py [SCENE] [-n 3] [--out observed.ply]
"""

import argparse
import pathlib

import numpy as np

import vantage

ROOT = pathlib.Path(__file__).resolve().parents[2]
# Colours per number of chosen sensors that see a cell: 0, 1, 2, 3+ (RGB in 0..1).
COLOURS = np.array([[0.6, 0.6, 0.6], [0.2, 0.7, 0.3], [0.1, 0.6, 0.6], [0.2, 0.3, 0.9]])


def observed_cells(vis, selection):
    """(R, 3) cell centres [m] and the number of chosen sensors seeing each cell."""
    counts = np.asarray(vis.matrix[selection.indices].sum(axis=0)).ravel().astype(int)
    return vis.reference, counts


def to_open3d(points, colours):
    """An open3d.geometry.PointCloud, or None without Open3D."""
    try:
        import open3d as o3d
    except ImportError:
        return None
    cloud = o3d.geometry.PointCloud()
    cloud.points = o3d.utility.Vector3dVector(points)
    cloud.colors = o3d.utility.Vector3dVector(colours)
    return cloud


def write_ply(path, points, colours):
    """ASCII PLY of points [m] with 8-bit colours, NumPy only."""
    rgb = np.round(255 * colours).astype(np.uint8)
    with open(path, "w", encoding="ascii") as f:
        f.write("ply\nformat ascii 1.0\ncomment vantage observed cells, centres in metres\n"
                f"element vertex {len(points)}\nproperty double x\nproperty double y\n"
                "property double z\nproperty uchar red\nproperty uchar green\n"
                "property uchar blue\nend_header\n")
        for p, c in zip(points, rgb):
            f.write(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g} {c[0]} {c[1]} {c[2]}\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=ROOT / "examples/scenes/bin_picking_cell.yaml")
    parser.add_argument("-n", type=int, default=3, help="sensors to choose")
    parser.add_argument("--method", default="local")
    parser.add_argument("--out", default="observed.ply")
    parser.add_argument("--seen-only", action="store_true", help="leave out unobserved cells")
    args = parser.parse_args()

    vis = vantage.load(args.scene).observe()
    selection = vis.select(n=args.n, method=args.method)
    points, counts = observed_cells(vis, selection)
    if args.seen_only:
        points, counts = points[counts > 0], counts[counts > 0]
    colours = COLOURS[np.minimum(counts, 3)]
    print(f"{selection.method} n={selection.n}: {', '.join(selection.sensors)}; coverage "
          f"{100 * selection.coverage:.2f} %, {int((counts > 0).sum())} of {len(counts)} cells "
          "observed")
    cloud = to_open3d(points, colours)
    if cloud is not None:
        import open3d as o3d
        o3d.io.write_point_cloud(args.out, cloud, write_ascii=True)
        print(f"open3d.geometry.PointCloud of {len(cloud.points)} points written to {args.out}")
    else:
        write_ply(args.out, points, colours)
        print(f"Open3D not installed: {len(points)} points written to {args.out} with NumPy")


if __name__ == "__main__":
    main()
