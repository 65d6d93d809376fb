#!/usr/bin/env python3
"""Renders an interface mesh written by vdb_interfaces (binary .ply with the face properties
label0, label1) to a PNG, one colour per label pair, lit from the viewer.

Needs python3-numpy and python3-matplotlib (Debian packages; not part of the set-up).

    python3 tools/render_picture.py build/knight.ply tools/images/knight.png \
        --without 0 --title "chr_knight.vox"

--without L adds a second panel that hides the patches touching label L (usually the
background), which shows the interfaces inside the volume.
"""

import argparse
import sys

import numpy as np

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "<i2", "ushort": "<u2", "int": "<i4",
             "uint": "<u4", "float": "<f4", "double": "<f8",
             "int8": "i1", "uint8": "u1", "int32": "<i4", "uint32": "<u4", "float32": "<f4"}


def read_ply(path):
    """Points (n x 3), triangles (m x 3) and label pairs (m x 2) of a binary little-endian PLY
    with triangle faces."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            sys.exit(f"{path}: not a PLY file")
        elements = []  # [name, count, [(property name, dtype or (count dtype, item dtype))]]
        while True:
            words = f.readline().decode("ascii").split()
            if not words:
                continue
            if words[0] == "format" and words[1] != "binary_little_endian":
                sys.exit(f"{path}: only binary_little_endian PLY is supported")
            elif words[0] == "element":
                elements.append([words[1], int(words[2]), []])
            elif words[0] == "property" and words[1] == "list":
                elements[-1][2].append((words[4], (PLY_TYPES[words[2]], PLY_TYPES[words[3]])))
            elif words[0] == "property":
                elements[-1][2].append((words[2], PLY_TYPES[words[1]]))
            elif words[0] == "end_header":
                break
        data = {}
        for name, count, props in elements:
            fields = []
            for prop, kind in props:
                if isinstance(kind, tuple):  # a list: vdb_interfaces writes triangles only
                    fields += [(prop + "_n", kind[0]), (prop, kind[1], (3,))]
                else:
                    fields.append((prop, kind))
            data[name] = np.fromfile(f, dtype=np.dtype(fields), count=count)
    vertex, face = data["vertex"], data["face"]
    if face.size and np.any(face["vertex_indices_n"] != 3):
        sys.exit(f"{path}: faces must be triangles")
    if "label0" not in face.dtype.names:
        sys.exit(f"{path}: no face properties label0, label1 (not written by vdb_interfaces?)")
    points = np.stack([vertex["x"], vertex["y"], vertex["z"]], axis=1).astype(np.float64)
    return points, face["vertex_indices"].astype(np.int64), \
        np.stack([face["label0"], face["label1"]], axis=1)


def view_matrix(azimuth, elevation):
    """Rows: screen x, screen y, towards the viewer; z is up in the volume."""
    a, e = np.radians(azimuth), np.radians(elevation)
    towards = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.cross(towards, right)
    return np.stack([right, up, towards])


def pair_colours(pairs):
    """One colour per distinct label pair, the same for the same pair in every panel."""
    unique, index = np.unique(pairs, axis=0, return_inverse=True)
    palette = np.concatenate([plt.get_cmap("tab20")(np.arange(20))[:, :3],
                              plt.get_cmap("tab20b")(np.arange(20))[:, :3]])
    # Spread neighbouring pairs over the palette so that adjacent patches differ.
    order = (np.arange(len(unique)) * 7) % len(palette)
    return palette[order][index.ravel()], len(unique)


def shading(corners, colours):
    """Lambert shading, two-sided, light from the viewer."""
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(normals, axis=1)
    light = np.abs(normals[:, 2]) / np.where(length > 0, length, 1.0)
    return colours * (0.35 + 0.65 * light)[:, None]


def draw_polygons(ax, corners, colours, edges):
    """Painter's algorithm, far triangles first: exact enough for small meshes."""
    shaded = shading(corners, colours)
    order = np.argsort(corners[:, :, 2].mean(axis=1))
    polygons = PolyCollection(corners[order, :, :2], facecolors=shaded[order],
                              edgecolors=(0, 0, 0, 0.15) if edges else shaded[order],
                              linewidths=0.15 if edges else 0.1, antialiaseds=False)
    ax.add_collection(polygons)
    ax.autoscale_view()


def draw_splats(ax, corners, colours, pixels):
    """Z-buffer of a few points per triangle: for meshes whose triangles are about a pixel."""
    shaded = shading(corners, colours)
    low, high = corners.reshape(-1, 3).min(axis=0), corners.reshape(-1, 3).max(axis=0)
    scale = (pixels - 1) / max(high[0] - low[0], high[1] - low[1])
    width, height = (np.ceil((high[:2] - low[:2]) * scale).astype(int) + 1)
    depth = np.full(width * height, -np.inf)
    image = np.ones((width * height, 3))
    for weights in ([1, 1, 1], [4, 1, 1], [1, 4, 1], [1, 1, 4]):
        sample = np.tensordot(corners, np.array(weights) / sum(weights), axes=([1], [0]))
        column = ((sample[:, 0] - low[0]) * scale).round().astype(int)
        row = ((high[1] - sample[:, 1]) * scale).round().astype(int)
        pixel = row * width + column
        order = np.lexsort((sample[:, 2], pixel))  # by pixel, the nearest last
        last = np.append(pixel[order][1:] != pixel[order][:-1], True)
        best, nearest = pixel[order][last], order[last]
        closer = sample[nearest, 2] > depth[best]
        depth[best[closer]] = sample[nearest[closer], 2]
        image[best[closer]] = shaded[nearest[closer]]
    ax.imshow(image.reshape(height, width, 3), interpolation="antialiased")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("ply", help="binary PLY written by vdb_interfaces -o FILE.ply")
    parser.add_argument("png", help="picture to write")
    parser.add_argument("--azimuth", type=float, default=-60.0, help="degrees (default -60)")
    parser.add_argument("--elevation", type=float, default=25.0, help="degrees (default 25)")
    parser.add_argument("--without", type=int, metavar="L",
                        help="add a panel without the patches touching label L")
    parser.add_argument("--edges", action="store_true", help="outline every triangle")
    parser.add_argument("--title", default="", help="caption above the picture")
    parser.add_argument("--width", type=float, default=10.0, help="inches (default 10)")
    parser.add_argument("--dpi", type=int, default=100)
    parser.add_argument("--polygons", type=int, default=300000, metavar="N",
                        help="draw up to N triangles as polygons, more as z-buffered points "
                             "(default 300000)")
    args = parser.parse_args()

    points, triangles, pairs = read_ply(args.ply)
    colours, pair_count = pair_colours(pairs)
    rotation = view_matrix(args.azimuth, args.elevation)

    panels = [(np.ones(len(triangles), bool), f"all {pair_count} label pairs")]
    if args.without is not None:
        keep = np.all(pairs != args.without, axis=1)
        panels.append((keep, f"without the patches of label {args.without}"))
    fig, axes = plt.subplots(1, len(panels), squeeze=False,
                             figsize=(args.width, args.width * 0.75 / len(panels) + 0.4))
    for ax, (keep, caption) in zip(axes[0], panels):
        corners = points[triangles[keep]] @ rotation.T  # triangles x 3 x 3, z to the viewer
        if keep.sum() <= args.polygons:
            draw_polygons(ax, corners, colours[keep], args.edges)
        else:
            draw_splats(ax, corners, colours[keep], args.width * args.dpi / len(panels))
        ax.set_aspect("equal")
        ax.axis("off")
        ax.set_title(f"{caption}: {int(keep.sum())} triangles", fontsize=10)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=args.dpi)
    print(f"{args.png}: {len(triangles)} triangles, {pair_count} label pairs")


if __name__ == "__main__":
    main()
