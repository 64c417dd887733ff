#!/usr/bin/python3
"""Pictures of a warpchol run: its PVD series as PNG frames and a contact sheet.

    xvfb-run -a python/render_run.py output/torus_pull/torus_pull.pvd

reads the VTU files the PVD lists (written by build/warpchol: per vertex displacement,
velocity and, in a scene with cuts or grasps, grasped; per cell rerotated,
steps_since_rerotation, error_estimate, body, removed and cut_step), draws the body in its
deformed shape coloured by a field, hides the cells a cut removed, marks the grasped
vertices, draws the obstacles of a scene with contact (part 1 of the PVD), and writes

    OUT/SCENE-FIELD-NNNNN.png   one frame per step (--no-frames: none)
    OUT/SCENE-FIELD-sheet.png   a grid of --sheet frames spread over the run

OUT is the PVD's folder unless --out says otherwise. Every frame of a run has the same
camera and the same colour range, so that frames compare. The VTU files carry no
instruments (tool, blade, jaws); the grasped vertices stand for the jaws.

Rendering is offscreen, but Debian's VTK (python3-vtk9) opens an X display all the same:
run the script under xvfb-run -a (package xvfb). Errors are one line on standard error,
with exit status 2 for bad input (a missing or broken file, a field the run does not
have) and 1 for anything else.
"""

import argparse
import math
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

PROGRAM = "render_run.py"


class InputError(Exception):
    """Bad input, reported in one line with exit status 2."""


# --------------------------------------------------------------------------------------
# The run: the PVD's records and the scene's material
# --------------------------------------------------------------------------------------

def read_pvd(path, part="0"):
    """The (time, step, VTU path) records of the PVD at @p path, in the order of time: the
    body's (part 0, or no part), or with @p part = "1" the obstacles' files that a scene
    with contact writes beside them (none otherwise)."""
    if not os.path.isfile(path):
        raise InputError(f"{path}: no such file")
    try:
        root = ElementTree.parse(path).getroot()
    except ElementTree.ParseError as error:
        raise InputError(f"{path}: not a PVD file ({error})") from None
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        raise InputError(f"{path}: not a PVD file (no VTKFile of type Collection)")
    folder = os.path.dirname(path)
    records = []
    for dataset in root.iter("DataSet"):
        name, time = dataset.get("file"), dataset.get("timestep")
        if dataset.get("part", "0") != part:
            continue
        if name is None or time is None:
            raise InputError(f"{path}: a DataSet without file or timestep")
        try:
            time = float(time)
        except ValueError:
            raise InputError(f"{path}: timestep {time!r} is not a number") from None
        # build/warpchol names its files SCENE-NNNNN.vtu (or .pvtu): NNNNN is the step.
        match = re.search(r"-(\d+)\.p?vtu$", name)
        step = int(match.group(1)) if match else len(records)
        records.append((time, step, os.path.join(folder, name)))
    if not records and part == "0":
        raise InputError(f"{path}: the PVD lists no data sets")
    return sorted(records)


def obstacle_surface(vtk, path):
    """The obstacles' triangles of one frame (SCENE-obstacles-NNNNN.vtu) as polydata."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetOutput().GetNumberOfCells() == 0:
        raise InputError(f"{path}: no obstacle triangles")
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputConnection(reader.GetOutputPort())
    normals = vtk.vtkPolyDataNormals()
    normals.SetInputConnection(surface.GetOutputPort())
    normals.SetFeatureAngle(50)
    normals.Update()
    return normals.GetOutput()


def read_material(prm):
    """Young's modulus and Poisson's ratio of the Material subsection of the parameter file
    @p prm (its includes followed, relative to the including file's folder)."""
    values = {}

    def read(path, depth):
        if not os.path.isfile(path):
            raise InputError(f"{path}: no such file")
        if depth > 16:
            raise InputError(f"{path}: includes nested too deep")
        subsection = []
        with open(path) as file:
            for line in file:
                line = line.split("#", 1)[0].strip()
                if line.startswith("include ") and not subsection:
                    read(os.path.join(os.path.dirname(path), line[len("include "):].strip()),
                         depth + 1)
                elif line.startswith("subsection "):
                    subsection.append(line[len("subsection "):].strip())
                elif line == "end" and subsection:
                    subsection.pop()
                elif line.startswith("set ") and subsection == ["Material"] and "=" in line:
                    key, value = line[4:].split("=", 1)
                    values[key.strip()] = value.strip()

    read(prm, 0)
    try:
        return float(values["Young's modulus"]), float(values["Poisson's ratio"])
    except (KeyError, ValueError):
        raise InputError(f"{prm}: no Material/Young's modulus and Poisson's ratio") from None


# --------------------------------------------------------------------------------------
# Reading a VTU and making the picture's data set
# --------------------------------------------------------------------------------------

def import_vtk():
    """VTK's modules, or an InputError saying what to install or how to run."""
    if not os.environ.get("DISPLAY"):
        raise InputError("no X display: run it under xvfb-run -a (Debian package xvfb)")
    try:
        import vtkmodules.all as vtk
        from vtkmodules.util import numpy_support
        import numpy
    except ImportError as error:
        raise InputError(f"no VTK for this Python ({error}): Debian's python3-vtk9 is "
                         f"for /usr/bin/python3") from None
    return vtk, numpy_support, numpy


# Fields that belong to cells. deal.II's DataOut (VTU precision = float32, the default)
# writes every cell with vertices of its own and its cell fields as values at those
# vertices; warpchol's own float64 files write each vertex once and cell fields per cell.
CELL_FIELDS = ("rerotated", "steps_since_rerotation", "error_estimate", "body", "removed", "cut_step")


class Run:
    """The frames of a run, read and prepared for drawing with one field."""

    def __init__(self, vtk, numpy_support, numpy, field, material, show_cut):
        self.vtk, self.ns, self.np = vtk, numpy_support, numpy
        self.field, self.material, self.show_cut = field, material, show_cut

    def read(self, path):
        """The tetrahedra of the VTU or PVTU file @p path, each vertex once: rest positions,
        cells (n x 4 vertex numbers), point fields and cell fields as NumPy arrays."""
        vtk, np, ns = self.vtk, self.np, self.ns
        if not os.path.isfile(path):
            raise InputError(f"{path}: no such file (listed in the PVD)")
        reader = (vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu")
                  else vtk.vtkXMLUnstructuredGridReader())
        errors = []
        reader.AddObserver("ErrorEvent", lambda caller, event: errors.append(event))
        reader.SetFileName(path)
        # A broken file's errors come from the reader's parser and pipeline, many lines
        # each: silenced here, reported below in one line.
        vtk.vtkObject.GlobalWarningDisplayOff()
        reader.Update()
        vtk.vtkObject.GlobalWarningDisplayOn()
        grid = reader.GetOutput()
        if errors or reader.GetErrorCode() != 0 or grid is None or grid.GetNumberOfCells() == 0:
            raise InputError(f"{path}: not a readable VTU file with cells")
        offsets = ns.vtk_to_numpy(grid.GetCells().GetOffsetsArray())
        if np.any(np.diff(offsets) != 4):
            raise InputError(f"{path}: cells other than tetrahedra (not written by warpchol?)")
        cells = ns.vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 4)
        points = ns.vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
        point_fields, cell_fields = {}, {}
        data = grid.GetPointData()
        for i in range(data.GetNumberOfArrays()):
            values = ns.vtk_to_numpy(data.GetArray(i)).astype(float)
            if data.GetArrayName(i) in CELL_FIELDS:
                cell_fields[data.GetArrayName(i)] = values[cells[:, 0]]
            else:
                point_fields[data.GetArrayName(i)] = values
        data = grid.GetCellData()
        for i in range(data.GetNumberOfArrays()):
            cell_fields[data.GetArrayName(i)] = ns.vtk_to_numpy(data.GetArray(i)).astype(float)
        if "displacement" not in point_fields:
            raise InputError(f"{path}: no point field 'displacement' (not written by warpchol?)")
        # Each vertex once: equal positions of one body are one vertex (deal.II's copies are
        # exact).
        body = np.zeros(len(points))
        if "body" in cell_fields:
            body[cells.ravel()] = np.repeat(cell_fields["body"], 4)
        keys = np.column_stack([points, body])
        _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        cells = inverse.reshape(-1)[cells]
        points, body = points[first], body[first]
        point_fields = {name: values[first] for name, values in point_fields.items()}
        # Several bodies are written side by side (Bodies/Spacing), but deal.II 9.4's
        # DataOut::merge_patches() drops the shift of patches built with a mapping: in
        # float32 files the bodies lie on top of each other. Drawn side by side here.
        n_bodies = int(body.max()) + 1
        if n_bodies > 1:
            boxes = [(points[body == b].min(axis=0), points[body == b].max(axis=0))
                     for b in range(n_bodies)]
            if all(np.allclose(box[0], boxes[0][0]) and np.allclose(box[1], boxes[0][1])
                   for box in boxes):
                spacing = 1.25 * (boxes[0][1][0] - boxes[0][0][0])
                points = points + np.outer(body, [spacing, 0.0, 0.0])
        return points, cells, point_fields, cell_fields

    def frame(self, path):
        """The body of one frame: deformed, cut cells hidden, the field as 'shown'."""
        vtk, np, ns = self.vtk, self.np, self.ns
        rest, cells, point_fields, cell_fields = self.read(path)
        displacement = point_fields["displacement"]

        # The field, as one scalar per point or per cell.
        if self.field == "stress":
            values, on_cells = self.von_mises_stress(rest, cells, displacement), True
        elif self.field in point_fields:
            values, on_cells = point_fields[self.field], False
        elif self.field in cell_fields:
            values, on_cells = cell_fields[self.field], True
        else:
            fields = sorted(set(point_fields) | set(cell_fields) | {"stress"})
            raise InputError(f"{path}: no field {self.field!r} (this run has: "
                             f"{', '.join(fields)})")
        if values.ndim == 2:
            values = np.linalg.norm(values, axis=1)

        # Cut cells (removed = 1) hidden.
        kept = np.ones(len(cells), dtype=bool)
        n_cut = 0
        if "removed" in cell_fields:
            n_cut = int(np.count_nonzero(cell_fields["removed"] > 0.5))
            if not self.show_cut:
                kept = cell_fields["removed"] <= 0.5
        if on_cells:
            values = values[kept]
        cells = cells[kept]
        # The colour range from what is drawn: a vertex a cut left in no cell is not.
        drawn_values = values if on_cells else values[np.unique(cells)]
        if len(cells) == 0:
            raise InputError(f"{path}: every cell is cut: nothing to draw (--show-cut draws them)")

        # The deformed shape: rest positions plus displacement.
        grid = vtk.vtkUnstructuredGrid()
        points = vtk.vtkPoints()
        points.SetData(ns.numpy_to_vtk(np.ascontiguousarray(rest + displacement), deep=True))
        grid.SetPoints(points)
        connectivity = np.hstack([np.full((len(cells), 1), 4), cells]).astype(np.int64).ravel()
        cell_array = vtk.vtkCellArray()
        cell_array.SetCells(len(cells), ns.numpy_to_vtkIdTypeArray(connectivity, deep=True))
        grid.SetCells(vtk.VTK_TETRA, cell_array)
        shown = ns.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        shown.SetName("shown")
        (grid.GetCellData() if on_cells else grid.GetPointData()).AddArray(shown)

        # Grasped vertices (grasped = 1), at their deformed positions.
        grasped_points = None
        if "grasped" in point_fields and np.any(point_fields["grasped"] > 0.5):
            grasped_points = (rest + displacement)[point_fields["grasped"] > 0.5]

        surface = vtk.vtkDataSetSurfaceFilter()
        surface.SetInputData(grid)
        # Smooth shading, but sharp where faces meet at more than 50 degrees (a cut's
        # faces, a box's edges).
        normals = vtk.vtkPolyDataNormals()
        normals.SetInputConnection(surface.GetOutputPort())
        normals.SetFeatureAngle(50)
        normals.SplittingOn()
        normals.Update()
        return {"surface": normals.GetOutput(), "on_cells": on_cells, "values": drawn_values,
                "grasped": grasped_points, "cut": n_cut}

    def von_mises_stress(self, rest, cells, displacement):
        """Per cell the von Mises stress of the corotated strain e = sym(R^T F) - I:
        sigma = lambda tr(e) I + 2 mu e, with the Material subsection's E and nu (plastic
        strains of material changes are not in the VTU and not counted)."""
        np = self.np
        if self.material is None:
            raise InputError("--field stress needs the scene's file: --prm SCENE.prm")
        young, poisson = self.material
        x_rest = rest[cells]
        x_now = x_rest + displacement[cells]
        d_rest = (x_rest[:, 1:] - x_rest[:, :1]).transpose(0, 2, 1)
        d_now = (x_now[:, 1:] - x_now[:, :1]).transpose(0, 2, 1)
        deformation = d_now @ np.linalg.inv(d_rest)
        u, singular, vt = np.linalg.svd(deformation)
        # e = V (S - I) V^T: the stretch of F's polar decomposition minus the identity (an
        # inverted element keeps one negative singular value); its principal values S - 1.
        flip = np.linalg.det(u @ vt) < 0
        singular[flip, 2] *= -1
        principal = singular - 1.0
        lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
        mu = young / (2 * (1 + poisson))
        sigma = lam * principal.sum(axis=1, keepdims=True) + 2 * mu * principal
        s1, s2, s3 = sigma[:, 0], sigma[:, 1], sigma[:, 2]
        return np.sqrt(0.5 * ((s1 - s2) ** 2 + (s2 - s3) ** 2 + (s3 - s1) ** 2))


# --------------------------------------------------------------------------------------
# Drawing
# --------------------------------------------------------------------------------------

# The colour bar's title per field, with its unit (the scenes are in SI units: parameters/).
FIELD_TITLES = {
    "displacement": "displacement magnitude (m)",
    "velocity": "speed (m/s)",
    "stress": "von Mises stress (Pa)",
    "rerotated": "element re-assembled by WCC in this step",
    "steps_since_rerotation": "steps since the element was re-assembled",
    "error_estimate": "WCC error estimate of the element (relative)",
    "cut_step": "step of the cut (-1: not cut)",
    "grasped": "vertex grasped",
    "body": "body",
}

# Fields of two values, drawn in two colours with a name each.
TWO_VALUES = {"rerotated": ("not re-rotated", "re-rotated"), "grasped": ("free", "grasped")}


def field_title(field):
    return FIELD_TITLES.get(field, field)


def nice_ticks(low, high, count=5):
    """Round numbers between @p low and @p high, about @p count of them."""
    span = high - low
    if span <= 0:
        return [low]
    raw = span / count
    magnitude = 10 ** math.floor(math.log10(raw))
    step = next(m * magnitude for m in (1, 2, 2.5, 5, 10) if m * magnitude >= raw)
    first = math.ceil(low / step - 1e-9) * step
    ticks = []
    value = first
    while value <= high + 1e-9 * span:
        ticks.append(0.0 if abs(value) < 1e-12 * span else value)
        value += step
    return ticks


def lookup_table(vtk, field, low, high):
    """The colours of @p field from @p low to @p high."""
    table = vtk.vtkLookupTable()
    if field in TWO_VALUES:
        table.SetNumberOfTableValues(2)
        table.SetTableValue(0, 0.80, 0.84, 0.90, 1.0)
        table.SetTableValue(1, 0.93, 0.42, 0.08, 1.0)
        table.SetTableRange(0, 1)
        table.IndexedLookupOn()
        for value, name in enumerate(TWO_VALUES[field]):
            table.SetAnnotation(vtk.vtkVariant(float(value)), name)
        table.Build()
        return table
    # A sequential map from pale blue-grey (tissue at rest) through yellow and orange to
    # dark red, over 256 entries: the still parts stay light, the moved ones warm.
    anchors = [(0.0, (0.84, 0.87, 0.92)), (0.3, (0.99, 0.86, 0.47)),
               (0.65, (0.95, 0.45, 0.15)), (1.0, (0.60, 0.04, 0.10))]
    table.SetNumberOfTableValues(256)
    for i in range(256):
        t = i / 255
        for (t0, c0), (t1, c1) in zip(anchors, anchors[1:]):
            if t <= t1:
                w = (t - t0) / (t1 - t0)
                table.SetTableValue(i, *[a + w * (b - a) for a, b in zip(c0, c1)], 1.0)
                break
    table.SetTableRange(low, high if high > low else low + 1)
    table.Build()
    return table


def add_text(vtk, renderer, text, size, position, bold=False, justify="left",
             vertical="bottom"):
    actor = vtk.vtkTextActor()
    actor.SetInput(text)
    prop = actor.GetTextProperty()
    prop.SetFontSize(size)
    prop.SetColor(0.1, 0.1, 0.1)
    prop.SetBold(bold)
    prop.SetFontFamilyToArial()
    {"left": prop.SetJustificationToLeft, "center": prop.SetJustificationToCentered,
     "right": prop.SetJustificationToRight}[justify]()
    {"bottom": prop.SetVerticalJustificationToBottom, "top": prop.SetVerticalJustificationToTop,
     "center": prop.SetVerticalJustificationToCentered}[vertical]()
    actor.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    actor.GetPositionCoordinate().SetValue(*position)
    renderer.AddActor2D(actor)
    return actor


def body_actors(vtk, frame, table, radius, edges):
    """The body's surface coloured by 'shown', its edges faint (if @p edges), and the
    grasped vertices."""
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(frame["surface"])
    mapper.SetLookupTable(table)
    mapper.SetUseLookupTableScalarRange(True)
    if frame["on_cells"]:
        mapper.SetScalarModeToUseCellFieldData()
    else:
        mapper.SetScalarModeToUsePointFieldData()
        mapper.InterpolateScalarsBeforeMappingOn()
    mapper.SelectColorArray("shown")
    mapper.ScalarVisibilityOn()
    body = vtk.vtkActor()
    body.SetMapper(mapper)
    body.GetProperty().SetEdgeVisibility(edges)
    body.GetProperty().SetEdgeColor(0.42, 0.42, 0.45)
    body.GetProperty().SetLineWidth(0.5)
    body.GetProperty().SetAmbient(0.45)
    body.GetProperty().SetDiffuse(0.65)
    actors = [body]
    if frame["grasped"] is not None:
        points = vtk.vtkPoints()
        for p in frame["grasped"]:
            points.InsertNextPoint(*p)
        cloud = vtk.vtkPolyData()
        cloud.SetPoints(points)
        sphere = vtk.vtkSphereSource()
        sphere.SetRadius(radius)
        sphere.SetThetaResolution(12)
        sphere.SetPhiResolution(12)
        glyphs = vtk.vtkGlyph3D()
        glyphs.SetInputData(cloud)
        glyphs.SetSourceConnection(sphere.GetOutputPort())
        glyph_mapper = vtk.vtkPolyDataMapper()
        glyph_mapper.SetInputConnection(glyphs.GetOutputPort())
        glyph_mapper.ScalarVisibilityOff()
        grasp = vtk.vtkActor()
        grasp.SetMapper(glyph_mapper)
        grasp.GetProperty().SetColor(0.10, 0.25, 0.85)
        grasp.GetProperty().SetAmbient(0.5)
        actors.append(grasp)
    if frame.get("obstacles") is not None:
        # The rigid obstacles and instruments: grey, a little transparent.
        obstacle_mapper = vtk.vtkPolyDataMapper()
        obstacle_mapper.SetInputData(frame["obstacles"])
        obstacle_mapper.ScalarVisibilityOff()
        obstacles = vtk.vtkActor()
        obstacles.SetMapper(obstacle_mapper)
        obstacles.GetProperty().SetColor(0.62, 0.64, 0.68)
        obstacles.GetProperty().SetOpacity(0.75)
        obstacles.GetProperty().SetAmbient(0.35)
        actors.append(obstacles)
    return actors


class View:
    """One camera for every frame: looking along an axis, turned by azimuth and elevation,
    in parallel projection, fitted to the points of all frames drawn."""

    DIRECTIONS = {"x": (1, 0, 0), "-x": (-1, 0, 0), "y": (0, 1, 0), "-y": (0, -1, 0),
                  "z": (0, 0, 1), "-z": (0, 0, -1)}
    UPS = {"x": (0, 1, 0), "-x": (0, 1, 0), "y": (0, 0, -1), "-y": (0, 0, 1),
           "z": (0, 1, 0), "-z": (0, 1, 0)}

    def __init__(self, vtk, np, points, view, up, azimuth, elevation, zoom):
        center = 0.5 * (points.min(axis=0) + points.max(axis=0))
        camera = vtk.vtkCamera()
        camera.SetFocalPoint(*center)
        camera.SetPosition(*(center + np.array(self.DIRECTIONS[view], dtype=float)))
        camera.SetViewUp(*(self.UPS[view] if up is None else self.DIRECTIONS[up]))
        camera.Azimuth(azimuth)
        camera.Elevation(elevation)
        camera.OrthogonalizeViewUp()
        forward = center - np.array(camera.GetPosition())
        forward /= np.linalg.norm(forward)
        self.up = np.array(camera.GetViewUp())
        self.right = np.cross(forward, self.up)
        self.forward, self.center, self.zoom = forward, center, zoom
        relative = points - center
        x, y = relative @ self.right, relative @ self.up
        self.x_range, self.y_range = (x.min(), x.max()), (y.min(), y.max())
        self.depth = np.linalg.norm(points.max(axis=0) - points.min(axis=0))

    def apply(self, renderer, aspect, top_margin):
        """Fit the camera of @p renderer (width / height @p aspect) to the points, leaving
        the fraction @p top_margin of the height free for a caption."""
        free = 1.0 - top_margin
        width = self.x_range[1] - self.x_range[0]
        height = self.y_range[1] - self.y_range[0]
        scale = 1.06 * max(height / (2 * free), width / (2 * aspect)) / self.zoom
        mid_x = 0.5 * sum(self.x_range)
        # The body's middle at the middle of the part below the caption.
        mid_y = 0.5 * sum(self.y_range) + top_margin * scale
        focal = self.center + mid_x * self.right + mid_y * self.up
        camera = renderer.GetActiveCamera()
        camera.ParallelProjectionOn()
        camera.SetFocalPoint(*focal)
        camera.SetPosition(*(focal - 2 * self.depth * self.forward))
        camera.SetViewUp(*self.up)
        camera.SetParallelScale(scale)
        camera.SetClippingRange(0.5 * self.depth, 3.5 * self.depth)


def scalar_bar(vtk, table, field, low, high):
    """A horizontal colour bar, its labels above it, for the band under the frames (its
    title is a text below it: the bar's own title would overlap the labels)."""
    bar = vtk.vtkScalarBarActor()
    if field in TWO_VALUES:
        # The bar of an indexed table draws annotated swatches only: two plain entries.
        plain = vtk.vtkLookupTable()
        plain.DeepCopy(table)
        plain.IndexedLookupOff()
        plain.SetTableRange(0, 1)
        table = plain
    bar.SetLookupTable(table)
    bar.SetTitle("")
    bar.UnconstrainedFontSizeOn()
    bar.SetOrientationToHorizontal()
    bar.SetTextPositionToSucceedScalarBar()
    if field in TWO_VALUES:
        # The names of the two values are texts above the bar (render_grid): the bar's
        # annotations would not fit in the band.
        bar.SetDrawAnnotations(False)
        bar.SetDrawTickLabels(False)
    else:
        ticks = vtk.vtkDoubleArray()
        for tick in nice_ticks(low, high):
            ticks.InsertNextValue(tick)
        bar.SetUseCustomLabels(True)
        bar.SetCustomLabels(ticks)
        bar.SetLabelFormat("%g")
        bar.SetDrawAnnotations(False)
    for prop in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty(),
                 bar.GetAnnotationTextProperty()):
        prop.SetColor(0.1, 0.1, 0.1)
        prop.SetFontFamilyToArial()
        prop.ShadowOff()
        prop.ItalicOff()
        prop.BoldOff()
        prop.SetFontSize(18)
    bar.GetTitleTextProperty().SetFontSize(20)
    bar.SetBarRatio(0.45)
    bar.SetTextPad(3)
    bar.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    bar.GetPositionCoordinate().SetValue(0.2, 0.30)
    bar.SetWidth(0.6)
    bar.SetHeight(0.68)
    return bar


def background(renderer):
    # Flat: a gradient makes the PNG files several times larger.
    renderer.SetBackground(0.95, 0.96, 0.98)


def tile_caption(step, time, frame):
    text = f"step {step}, t = {time:.3g} s"
    if frame["cut"]:
        text += f", {frame['cut']} cells cut"
    if frame["grasped"] is not None:
        text += f", {len(frame['grasped'])} vertices grasped"
    return text


def render_grid(vtk, window, path, tiles, columns, tile_size, title, view, table, bar_title,
                field, low, high, radius, edges, surface_cells):
    """One PNG: @p title in a band on top, the @p tiles ((caption, frame) pairs) in a grid
    of @p columns, the colour bar in a band below; drawn in @p window (one for all: each
    window is a connection to the X server)."""
    columns = min(columns, len(tiles))
    rows = math.ceil(len(tiles) / columns)
    tile_w, tile_h = tile_size
    title_h, bar_h = 50, 96
    total_w, total_h = columns * tile_w, rows * tile_h + title_h + bar_h
    window.GetRenderers().RemoveAllItems()
    window.SetSize(total_w, total_h)

    top = vtk.vtkRenderer()
    top.SetViewport(0, (total_h - title_h) / total_h, 1, 1)
    top.SetBackground(1, 1, 1)
    add_text(vtk, top, title, 24, (0.5, 0.5), bold=True, justify="center", vertical="center")
    window.AddRenderer(top)
    caption_margin = 0.12 if any(caption for caption, _ in tiles) else 0.02
    for index, (caption, frame) in enumerate(tiles):
        row, column = divmod(index, columns)
        y1 = (total_h - title_h - row * tile_h) / total_h
        renderer = vtk.vtkRenderer()
        renderer.SetViewport(column * tile_w / total_w, y1 - tile_h / total_h,
                             (column + 1) * tile_w / total_w, y1)
        background(renderer)
        # Edges where they stay apart: up to about one surface triangle per 100 pixels, in
        # the frame of the run with the most (the same look in every frame).
        show_edges = edges == "on" or edges == "auto" and surface_cells * 100 < tile_w * tile_h
        for actor in body_actors(vtk, frame, table, radius, show_edges):
            renderer.AddActor(actor)
        if caption:
            add_text(vtk, renderer, caption, 18, (0.03, 0.965), vertical="top")
        light = vtk.vtkLight()
        light.SetLightTypeToHeadlight()
        light.SetIntensity(0.35)
        renderer.AddLight(light)
        window.AddRenderer(renderer)
        view.apply(renderer, tile_w / tile_h, caption_margin)
    bottom = vtk.vtkRenderer()
    bottom.SetViewport(0, 0, 1, bar_h / total_h)
    bottom.SetBackground(1, 1, 1)
    bottom.AddActor2D(scalar_bar(vtk, table, field, low, high))
    add_text(vtk, bottom, bar_title, 20, (0.5, 0.06), justify="center", vertical="bottom")
    if field in TWO_VALUES:
        for x, name in zip((0.35, 0.65), TWO_VALUES[field]):
            add_text(vtk, bottom, name, 18, (x, 0.66), justify="center", vertical="bottom")
    window.AddRenderer(bottom)

    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetCompressionLevel(9)
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    if writer.GetErrorCode() != 0 or not os.path.isfile(path):
        raise OSError(f"{path}: cannot write the PNG")


# --------------------------------------------------------------------------------------
# The program
# --------------------------------------------------------------------------------------

def parse_size(text):
    match = re.fullmatch(r"(\d+)x(\d+)", text)
    if not match or min(int(match.group(1)), int(match.group(2))) < 64:
        raise argparse.ArgumentTypeError(f"{text!r} is not WIDTHxHEIGHT (at least 64x64)")
    return int(match.group(1)), int(match.group(2))


def parse_range(text):
    try:
        low, high = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not MIN,MAX") from None
    if not high > low:
        raise argparse.ArgumentTypeError(f"{text!r}: MAX must exceed MIN")
    return low, high


def parse_steps(text):
    try:
        return sorted({int(v) for v in text.split(",")})
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a list of steps") from None


def arguments(argv):
    parser = argparse.ArgumentParser(
        prog=PROGRAM,
        description="PNG frames and a contact sheet of a warpchol run's PVD series "
                    "(run under xvfb-run -a).")
    parser.add_argument("pvd", help="the run's PVD file, output/SCENE/SCENE.pvd")
    parser.add_argument("--field", default="displacement",
                        help="colour by: displacement (default), velocity, stress (von Mises, "
                             "needs --prm), rerotated, steps_since_rerotation, error_estimate, "
                             "cut_step, or any field of the VTU files")
    parser.add_argument("--prm", help="the scene's parameter file (its Material: E and nu "
                                      "for --field stress)")
    parser.add_argument("--out", help="folder of the PNG files (default: the PVD's)")
    parser.add_argument("--name", help="file name stem (default: SCENE-FIELD)")
    parser.add_argument("--steps", type=parse_steps,
                        help="the steps to draw, e.g. 0,20,50 (default: every step of the PVD)")
    parser.add_argument("--sheet", type=int, default=6,
                        help="frames on the contact sheet, spread over the steps (default 6; 0: no sheet)")
    parser.add_argument("--columns", type=int, default=3, help="columns of the contact sheet (default 3)")
    parser.add_argument("--no-frames", action="store_true", help="write the contact sheet only")
    parser.add_argument("--size", type=parse_size, default=(800, 600),
                        help="size of a frame in pixels, WIDTHxHEIGHT (default 800x600)")
    parser.add_argument("--view", default="z", choices=["x", "-x", "y", "-y", "z", "-z"],
                        help="the axis the camera looks from (default z: from +z towards -z)")
    parser.add_argument("--up", choices=["x", "-x", "y", "-y", "z", "-z"],
                        help="the axis that points up in the picture (default y; -z when "
                             "looking from +y, z from -y)")
    parser.add_argument("--azimuth", type=float, default=25.0,
                        help="camera turned about the view-up axis, degrees (default 25)")
    parser.add_argument("--elevation", type=float, default=20.0,
                        help="camera raised, degrees (default 20)")
    parser.add_argument("--zoom", type=float, default=1.0, help="zoom past the fit (default 1)")
    parser.add_argument("--range", type=parse_range,
                        help="colour range MIN,MAX (default: 0 or the smallest value to the "
                             "largest over the frames drawn)")
    parser.add_argument("--edges", choices=["auto", "on", "off"], default="auto",
                        help="draw the surface's triangle edges (auto: where the mesh is coarse "
                             "enough for them to stay apart)")
    parser.add_argument("--show-cut", action="store_true", help="draw the cells a cut removed too")
    parser.add_argument("--title", help="the scene's name in the captions (default: the PVD's name)")
    options = parser.parse_args(argv)
    if options.sheet < 0 or options.columns < 1:
        parser.error("--sheet must be >= 0 and --columns >= 1")
    if options.no_frames and options.sheet == 0:
        parser.error("--no-frames with --sheet 0 writes nothing")
    return options


def spread(items, count):
    """@p count of @p items spread evenly, the first and the last included."""
    if count >= len(items):
        return list(items)
    if count == 1:
        return [items[-1]]
    return [items[round(i * (len(items) - 1) / (count - 1))] for i in range(count)]


def main(argv):
    options = arguments(argv)
    records = read_pvd(options.pvd)
    if options.steps is not None:
        wanted = set(options.steps)
        missing = wanted - {step for _, step, _ in records}
        if missing:
            raise InputError(f"{options.pvd}: no step {min(missing)} in the PVD (it has "
                             f"{', '.join(str(s) for _, s, _ in records)})")
        records = [r for r in records if r[1] in wanted]
    material = read_material(options.prm) if options.prm else None
    scene = options.title or os.path.splitext(os.path.basename(options.pvd))[0]
    out = options.out or os.path.dirname(options.pvd) or "."
    os.makedirs(out, exist_ok=True)
    stem = options.name or f"{scene}-{options.field}"

    vtk, numpy_support, numpy = import_vtk()
    run = Run(vtk, numpy_support, numpy, options.field, material, options.show_cut)
    sheet_records = spread(records, options.sheet) if options.sheet else []
    drawn = sheet_records if options.no_frames else records
    frames = {step: run.frame(path) for _, step, path in drawn}
    # A scene with contact: its obstacles where they are at each frame.
    for _, step, path in read_pvd(options.pvd, part="1"):
        if step in frames:
            frames[step]["obstacles"] = obstacle_surface(vtk, path)

    # One camera and one colour range for all frames.
    points = numpy.concatenate([numpy_support.vtk_to_numpy(f["surface"].GetPoints().GetData())
                                for f in frames.values()])
    view = View(vtk, numpy, points, options.view, options.up, options.azimuth,
                options.elevation, options.zoom)
    if options.range:
        low, high = options.range
    elif options.field in TWO_VALUES:
        low, high = 0.0, 1.0
    else:
        low = min(float(f["values"].min()) for f in frames.values())
        high = max(float(f["values"].max()) for f in frames.values())
        if low >= 0 and options.field not in ("cut_step", "body"):
            low = 0.0
        if high <= low:
            high = low + 1.0
    table = lookup_table(vtk, options.field, low, high)
    radius = 0.012 * float(numpy.linalg.norm(points.max(axis=0) - points.min(axis=0)))
    bar_title = field_title(options.field)
    surface_cells = max(f["surface"].GetNumberOfCells() for f in frames.values())

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(8)
    written = []
    if not options.no_frames:
        for time, step, _ in records:
            path = os.path.join(out, f"{stem}-{step:05d}.png")
            extra = tile_caption(step, time, frames[step]).split(", ", 2)[2:]
            title = f"{scene}: step {step}, t = {time:.3g} s" + "".join(", " + e for e in extra)
            render_grid(vtk, window, path, [("", frames[step])], 1, options.size, title, view, table,
                        bar_title, options.field, low, high, radius, options.edges,
                        surface_cells)
            written.append(path)
    if sheet_records:
        path = os.path.join(out, f"{stem}-sheet.png")
        width, height = options.size
        tiles = [(tile_caption(step, time, frames[step]), frames[step])
                 for time, step, _ in sheet_records]
        render_grid(vtk, window, path, tiles, options.columns, (width * 3 // 4, height * 3 // 4),
                    f"{scene}: {bar_title}", view, table, bar_title, options.field, low, high,
                    radius, options.edges, surface_cells)
        written.append(path)
    window.Finalize()

    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except InputError as error:
        print(f"{PROGRAM}: {error}", file=sys.stderr)
        sys.exit(2)
    except (OSError, RuntimeError, ValueError, MemoryError) as error:
        print(f"{PROGRAM}: {error}", file=sys.stderr)
        sys.exit(1)
