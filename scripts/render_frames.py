"""Renders a flexsens VTK series to PNG frames; run by ParaView's pvbatch (scripts/render-frames.sh).

    pvbatch render_frames.py RUN_DIR OUT_DIR [PARAM] [--every N] [--size WxH] [--no-tube] [--warp S]
                             [--view X,Y,Z]

RUN_DIR holds frames.pvd + frame_NNNNN.vtu as written by `flexsens run` (points at the current
positions, line cells, point data dq/d<param>). The lines (as tubes unless --no-tube) are
coloured by |dq/d<PARAM>| (default: the first dq/d* array) with one colour range for the whole
series (0 .. max over all frames) and a camera that frames the motion of all frames, so that
frames compare. Rigid bodies (element_kind 4, their basic frame A-B, A-C, A-D) are drawn as
solids: the box on the three edges when they are orthogonal (the satellite's cube), else the
tetrahedron of the four basic points, coloured by the same field (exact: a rigid body's
dq/dp is affine in its points). Meshed bodies (triangles, tetrahedra, linear or quadratic) are
surfaces in the field's colours with grey cell edges. The nodes of line elements are small
spheres in the field's colours. --warp S draws
the shape at q + S dq/dp. Writes OUT_DIR/frame_00000.png, frame_00001.png, ... (numbered
consecutively; with --every N output frame k is series frame k*N) and RUN_DIR/view.pvsm, a
ParaView state with the same pipeline (File > Load State). Exit code 1 on bad input.
"""
import argparse
import math
import os
import sys

# VTK's text renderer sends every string that contains '|' to matplotlib's mathtext, where '|'
# separates table columns and vanishes ("|dq/dp|" would show as "dq/dp"). Without matplotlib
# it falls back to FreeType, which draws the bars; no mathtext is needed here.
sys.modules["matplotlib"] = None


# Run inside ParaView's Programmable Filter: rigid bodies (cell data element_kind == 4: the
# lines A-B, A-C, A-D of one element_id) as a hexahedron (orthogonal edges) or a tetrahedron.
SOLIDS_SCRIPT = """
import builtins
import vtk
inp = self.GetInputDataObject(0, 0)
out = self.GetOutputDataObject(0)
kind = inp.GetCellData().GetArray('element_kind')
eid = inp.GetCellData().GetArray('element_id')
pts = vtk.vtkPoints()
out.SetPoints(pts)
out.Allocate(8)
pd_in = inp.GetPointData()
arrays = []
for i in range(pd_in.GetNumberOfArrays()):
    src = pd_in.GetArray(i)
    dst = src.NewInstance()
    dst.SetName(src.GetName())
    dst.SetNumberOfComponents(src.GetNumberOfComponents())
    out.GetPointData().AddArray(dst)
    arrays.append((src, dst))
bodies = {}
if kind is not None and eid is not None:
    for c in range(inp.GetNumberOfCells()):
        if int(kind.GetValue(c)) == 4:
            ids = inp.GetCell(c).GetPointIds()
            bodies.setdefault(int(eid.GetValue(c)), []).append((ids.GetId(0), ids.GetId(1)))
def add(weights):
    x = [0.0, 0.0, 0.0]
    for pid, w in weights:
        p = inp.GetPoint(pid)
        for k in range(3):
            x[k] += w * p[k]
    for src, dst in arrays:
        n = src.GetNumberOfComponents()
        v = [0.0] * n
        for pid, w in weights:
            t = src.GetTuple(pid)
            for k in range(n):
                v[k] += w * t[k]
        dst.InsertNextTuple(v)
    return pts.InsertNextPoint(x)
for b, edges in bodies.items():
    if len(edges) != 3 or len(builtins.set(e[0] for e in edges)) != 1:
        continue
    A = edges[0][0]
    B, C, D = (e[1] for e in edges)
    P = [inp.GetPoint(i) for i in (A, B, C, D)]
    e = [[P[j][k] - P[0][k] for k in range(3)] for j in (1, 2, 3)]
    dot = lambda u, v: builtins.sum(u[k] * v[k] for k in range(3))
    scale = builtins.max(dot(u, u) for u in e)
    ortho = builtins.all(builtins.abs(dot(e[i], e[j])) < 1e-6 * scale for i, j in ((0, 1), (0, 2), (1, 2)))
    if ortho:  # corners A + i (B - A) + j (C - A) + k (D - A), VTK's hexahedron order
        ids = []
        for i, j, k in ((0,0,0),(1,0,0),(1,1,0),(0,1,0),(0,0,1),(1,0,1),(1,1,1),(0,1,1)):
            w = {A: 1.0 - i - j - k}
            for pid, f in ((B, i), (C, j), (D, k)):
                w[pid] = w.get(pid, 0.0) + f
            ids.append(add(list(w.items())))
        out.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, ids)
    else:
        ids = [add([(pid, 1.0)]) for pid in (A, B, C, D)]
        out.InsertNextCell(vtk.VTK_TETRA, 4, ids)
"""


def fail(msg):
    sys.stderr.write("render_frames: %s\n" % msg)
    sys.stderr.flush()
    # pvbatch ignores SystemExit's code in some versions: leave the process directly.
    os._exit(1)


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="render_frames.py", description=__doc__.split("\n")[0])
    ap.add_argument("run_dir", help="directory with frames.pvd")
    ap.add_argument("out_dir", help="directory for frame_NNNNN.png")
    ap.add_argument("param", nargs="?", default=None,
                    help="design parameter (colours by |dq/d<param>|); default: the first dq/d* array")
    ap.add_argument("--every", type=int, default=1, metavar="N", help="render every N-th frame (default 1)")
    ap.add_argument("--size", default="1280x720", metavar="WxH", help="image size in pixels (default 1280x720)")
    ap.add_argument("--no-tube", action="store_true", help="draw plain lines instead of tubes")
    ap.add_argument("--warp", type=float, default=0.0, metavar="S",
                    help="draw the shape at q + S dq/d<param> (S in units of the parameter; default 0)")
    ap.add_argument("--view", default=None, metavar="X,Y,Z",
                    help="3-D scenes: camera direction, from the scene towards the camera (default: oblique)")
    ap.add_argument("--no-state", action="store_true",
                    help="do not write RUN_DIR/view.pvsm (a ParaView state with this pipeline)")
    try:
        a = ap.parse_args(argv)
    except SystemExit as e:
        if e.code:
            os._exit(1)
        os._exit(0)
    if a.every < 1:
        fail("--every must be a positive integer, got %d" % a.every)
    try:
        w, h = (int(v) for v in a.size.lower().split("x"))
        if w < 16 or h < 16:
            raise ValueError
    except ValueError:
        fail("--size must be WxH with W, H >= 16 pixels, got '%s'" % a.size)
    a.width, a.height = w, h
    if a.view is not None:
        try:
            a.view = [float(v) for v in a.view.split(",")]
            if len(a.view) != 3 or not any(v != 0.0 for v in a.view):
                raise ValueError
        except ValueError:
            fail("--view must be three numbers X,Y,Z, not all zero, got '%s'" % a.view)
    return a


def main(argv):
    a = parse_args(argv)
    pvd = os.path.join(a.run_dir, "frames.pvd")
    if not os.path.isfile(pvd):
        fail("no frames.pvd in %s (expected the output directory of `flexsens run`)" % a.run_dir)

    from paraview import simple as pv  # import late: argument errors need no ParaView start-up

    reader = pv.PVDReader(FileName=os.path.abspath(pvd))
    times = [float(t) for t in reader.TimestepValues] or [0.0]
    reader.UpdatePipeline(times[0])
    names = list(reader.PointData.keys())
    dq = [n for n in names if n.startswith("dq/d")]
    if not dq:
        fail("%s has no dq/d<param> point arrays (point arrays: %s); was it run with design parameters?"
             % (pvd, ", ".join(names) or "none"))
    param = a.param if a.param is not None else dq[0][len("dq/d"):]
    array = "dq/d" + param
    if array not in names:
        fail("no array '%s' in %s; parameters: %s" % (array, pvd, ", ".join(n[4:] for n in dq)))

    # --- one pass over all frames: colour range and bounds of the whole motion ------------
    vmax = 0.0
    bounds = [math.inf, -math.inf] * 3
    for t in times:
        reader.UpdatePipeline(t)
        info = reader.GetDataInformation()
        b = info.GetBounds()
        for i in range(3):
            bounds[2 * i] = min(bounds[2 * i], b[2 * i])
            bounds[2 * i + 1] = max(bounds[2 * i + 1], b[2 * i + 1])
        arr = reader.PointData[array]
        if arr is not None:
            vmax = max(vmax, arr.GetRange(-1)[1])  # -1: magnitude
    if not all(math.isfinite(v) for v in bounds):
        fail("%s has no points" % pvd)
    if not vmax > 0.0:
        vmax = 1.0  # all sensitivities zero: any positive range shows them as the low colour
    extent = [bounds[2 * i + 1] - bounds[2 * i] for i in range(3)]
    diag = math.sqrt(sum(e * e for e in extent)) or 1.0
    centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]

    # --- pipeline and view ------------------------------------------------------------------
    # sizes in pixels scale with the image height (designed for 720 lines)
    px = max(a.height / 720.0, 0.45)
    font = lambda size: max(int(round(size * px)), 7)
    # ParaView's built-in "Arial" draws '[' as '(' and 't' as a dagger: use DejaVu Sans
    # (fonts-dejavu-core) when it is there.
    font_file = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
    if not os.path.isfile(font_file):
        font_file = None

    def set_font(proxy, *prefixes):
        if font_file is None:
            return
        for pre in prefixes:
            try:
                setattr(proxy, pre + "FontFamily", "File")
                setattr(proxy, pre + "FontFile", font_file)
            except AttributeError:
                pass
    bar_x = 1.0 - (105.0 * px + 15.0) / a.width  # left edge of the colour bar (fraction)

    view = pv.CreateView("RenderView")
    view.ViewSize = [a.width, a.height]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.Background = [1.0, 1.0, 1.0]
    view.OrientationAxesVisibility = 0
    pv.SetActiveView(view)

    source = reader
    if a.warp != 0.0:
        source = pv.WarpByVector(Input=reader)
        source.Vectors = ["POINTS", array]
        source.ScaleFactor = a.warp
    if a.no_tube:
        shown = source
    else:
        surf = pv.ExtractSurface(Input=source)
        shown = pv.Tube(Input=surf)
        shown.Radius = 0.006 * diag
        shown.NumberofSides = 16
        shown.Capping = 1
    disp = pv.Show(shown, view)
    if a.no_tube:
        disp.LineWidth = 4.0
        try:
            disp.RenderLinesAsTubes = 1
        except AttributeError:
            pass
    pv.ColorBy(disp, ("POINTS", array, "Magnitude"))
    lut = pv.GetColorTransferFunction(array)
    try:
        lut.ApplyPreset("Viridis (matplotlib)", True)
    except Exception:
        pass
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, vmax)
    pv.GetOpacityTransferFunction(array).RescaleTransferFunction(0.0, vmax)

    # Meshed bodies (cell data element_kind 5 solid cells, 8 shell triangles) as surfaces in the
    # field's colours with thin grey cell edges (the tube filter above draws lines only): a
    # triangle mesh is its faces, a tetrahedral one its outer faces. By kind, not cell type: ParaView 5.11 cannot select quadratic cell types.
    def kind_only(k):
        f = pv.Threshold(Input=source)
        f.Scalars = ["CELLS", "element_kind"]
        try:
            f.LowerThreshold, f.UpperThreshold = k, k
            f.ThresholdMethod = "Between"
        except AttributeError:  # ParaView < 5.10
            f.ThresholdRange = [k, k]
        return f
    meshed = pv.AppendDatasets(Input=[kind_only(5), kind_only(8)])
    # Faces through their corners only: a quadratic face subdivided would draw its subdivision
    # lines as edges and hatch the colours.
    faces = pv.ExtractSurface(Input=meshed)
    faces.NonlinearSubdivisionLevel = 0
    faces_disp = pv.Show(faces, view)
    faces_disp.SetRepresentationType("Surface With Edges")
    faces_disp.EdgeColor = [0.4, 0.4, 0.4]
    pv.ColorBy(faces_disp, ("POINTS", array, "Magnitude"))

    # nodes as small spheres in the field's colours: joints visible, the field not hidden
    # (the nodes of line elements only: a meshed body shows its nodes as the corners of its
    # cell edges, and thousands of spheres would hide its surface)
    line_cells = pv.ExtractCellsByType(Input=source)
    line_cells.CellTypes = ["Line"]
    nodes = pv.Show(line_cells, view)
    nodes.SetRepresentationType("Points")
    nodes.PointSize = max(3.0, 7.0 * px)
    nodes.RenderPointsAsSpheres = 1
    pv.ColorBy(nodes, ("POINTS", array, "Magnitude"))

    bar = pv.GetScalarBar(lut, view)
    bar.Title = "|dq/d%s| [m per unit of %s]" % (param, param)
    bar.ComponentTitle = ""
    bar.Visibility = 1
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
    bar.TitleFontSize = font(16)
    bar.LabelFontSize = font(14)
    bar.ScalarBarThickness = font(16)
    set_font(bar, "Title", "Label")
    bar.RangeLabelFormat = "%-#.3g"
    bar.WindowLocation = "Any Location"
    bar.Orientation = "Vertical"
    bar.Position = [bar_x, 0.12]
    bar.ScalarBarLength = 0.7
    disp.SetScalarBarVisibility(view, True)

    label = pv.Text(Text="")
    ldisp = pv.Show(label, view)
    ldisp.WindowLocation = "Upper Left Corner"
    ldisp.Color = [0.0, 0.0, 0.0]
    ldisp.FontSize = font(18)
    set_font(ldisp, "")
    if a.width >= 640:  # no room for a title next to the time on small images
        title = pv.Text(Text="%s   colour: |dq/d%s|" % (os.path.basename(os.path.abspath(a.run_dir)), param))
        tdisp = pv.Show(title, view)
        tdisp.WindowLocation = "Upper Center"
        tdisp.Color = [0.0, 0.0, 0.0]
        tdisp.FontSize = font(16)
        set_font(tdisp, "")

    # axes grid with the bounds of the whole motion (fixed: no jumping tick marks)
    try:
        view.AxesGrid.Visibility = 1 if a.height >= 400 else 0  # labels would crowd small images
        view.AxesGrid.UseCustomBounds = 1
        view.AxesGrid.CustomBounds = bounds
        for ax in ("X", "Y", "Z"):
            setattr(view.AxesGrid, ax + "TitleColor", [0.2, 0.2, 0.2])
            setattr(view.AxesGrid, ax + "LabelColor", [0.2, 0.2, 0.2])
            setattr(view.AxesGrid, ax + "Title", ax + " [m]")
            set_font(view.AxesGrid, ax + "Title", ax + "Label")
        view.AxesGrid.GridColor = [0.6, 0.6, 0.6]
    except AttributeError:
        pass

    # --- camera: parallel projection fitted to the bounds of all frames ---------------------
    # Planar scenes (one extent ~0) are seen along their normal; 3-D ones from an oblique view.
    flat = [i for i in range(3) if extent[i] <= 1e-9 * diag]
    up = [0.0, 0.0, 1.0]
    if flat:
        n = flat[0]
        direction = [0.0, 0.0, 0.0]
        direction[n] = 1.0
        # up: Z unless Z is the normal (xy plane), then Y
        up = [0.0, 1.0, 0.0] if n == 2 else [0.0, 0.0, 1.0]
        if n == 1:
            direction = [0.0, -1.0, 0.0]  # xz plane: look along +Y so that X points right
        inplane = [i for i in range(3) if i != n]
        ih = 2 if n != 2 else 1  # index of the vertical axis
        iw = [i for i in inplane if i != ih][0]
        half_w, half_h = 0.5 * extent[iw], 0.5 * extent[ih]
    else:
        # oblique, turned towards the axis along which the motion is thinnest (a body swinging
        # in a plane is seen nearly face-on), or the --view direction
        direction = a.view or [b / (e / max(extent) + 0.25) for b, e in zip([1.0, -1.6, 0.9], extent)]
        if abs(direction[2]) > max(abs(direction[0]), abs(direction[1])):
            up = [0.0, 1.0, 0.0]  # seen mostly along Z: Y up
        norm = math.sqrt(sum(d * d for d in direction))
        direction = [d / norm for d in direction]
        half_w = half_h = 0.5 * diag
    # leave room for the colour bar on the right and the texts on top
    frac_w = bar_x - 0.06
    usable_w = frac_w * a.width
    usable_h = (0.80 if a.height >= 400 else 0.84) * a.height
    scale_w = half_w * a.height / usable_w
    scale_h = half_h * a.height / usable_h
    parallel = max(scale_w, scale_h, 0.05 * diag) * 1.08
    # shift the focal point so that the data sit left of the colour bar, below the texts
    shift_right = (0.5 - 0.5 * frac_w - 0.02) * a.width / a.height * 2 * parallel
    shift_up = 0.02 * 2 * parallel
    if flat:
        focal = list(centre)
        focal[iw] += shift_right
        focal[ih] += shift_up
    else:
        focal = list(centre)
    view.CameraParallelProjection = 1
    view.CameraFocalPoint = focal
    view.CameraPosition = [focal[i] + direction[i] * 3 * diag for i in range(3)]
    view.CameraViewUp = up
    view.CameraParallelScale = parallel

    # Rigid bodies as solids: the kind-4 cells of each body (A-B, A-C, A-D) become a box or a
    # tetrahedron with the field carried over by the same affine weights. Made last: ParaView
    # runs the filter's script in this module's namespace, where it shadows max, min, sum.
    solids = pv.ProgrammableFilter(Input=source)
    solids.OutputDataSetType = "vtkUnstructuredGrid"
    solids.Script = SOLIDS_SCRIPT
    solids_disp = pv.Show(solids, view)
    pv.ColorBy(solids_disp, ("POINTS", array, "Magnitude"))
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(0.0, vmax)  # ColorBy rescaled it to the solids' own range

    if not a.no_state:
        state = os.path.join(os.path.abspath(a.run_dir), "view.pvsm")
        try:
            pv.SaveState(state)
        except Exception as e:  # a read-only run directory: the pictures still come
            sys.stderr.write("render_frames: no state written (%s)\n" % e)

    # --- frames --------------------------------------------------------------------------
    os.makedirs(a.out_dir, exist_ok=True)
    selected = times[:: a.every]
    written = []
    for k, t in enumerate(selected):
        view.ViewTime = t
        label.Text = "t = %.4f s" % t
        path = os.path.join(a.out_dir, "frame_%05d.png" % k)
        pv.SaveScreenshot(path, view, ImageResolution=[a.width, a.height])
        if not os.path.isfile(path):
            fail("ParaView wrote no %s" % path)
        written.append(path)
    print("render_frames: %d PNG frames (%dx%d, every %d of %d) in %s; |%s| range 0 .. %.6g"
          % (len(written), a.width, a.height, a.every, len(times), os.path.abspath(a.out_dir), array, vmax))
    sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1:])
