#!/usr/bin/python3
"""Renders the immersed tour's picture (docs/immersed-tour.md) from `isospring analyze`'s
result.vtp of examples/immersed/rounded_bracket.json.

The bracket's surface (the B-rep's triangulation the program evaluates the fields on), deformed
by displacement_tip_down magnified SCALE times and coloured by von Mises stress, over the
undeformed surface's edges. Uses Debian's python3-vtk9 (VTK 9.1); it needs an X display, so run
it through scripts/render_immersed_tour.sh (xvfb-run) on a headless machine.

Usage: render_immersed_tour.py RESULT_DIR OUTPUT.png
"""
import sys

import vtk

from vtk_png import render_png

LOAD = "tip_down"
SCALE = 40.0  # the tip moves 0.17 mm on a 60 mm part: magnified to be seen


def main(result_dir, png):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(f"{result_dir}/result.vtp")
    reader.Update()
    surface = reader.GetOutput()
    if surface.GetPointData().GetArray(f"displacement_{LOAD}") is None:
        sys.exit(f"{result_dir}/result.vtp has no displacement_{LOAD}; run "
                 "`isospring analyze examples/immersed/rounded_bracket.json -o DIR` first")
    surface.GetPointData().SetActiveVectors(f"displacement_{LOAD}")
    warp = vtk.vtkWarpVector()
    warp.SetInputData(surface)
    warp.SetScaleFactor(SCALE)
    normals = vtk.vtkPolyDataNormals()  # smooth shading of the curved faces
    normals.SetInputConnection(warp.GetOutputPort())
    normals.SetFeatureAngle(40)

    stress = f"von_mises_{LOAD}"
    lo, hi = surface.GetPointData().GetArray(stress).GetRange()
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (low) to red (high)
    lut.SetTableRange(0, hi)
    lut.Build()
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(normals.GetOutputPort())
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(stress)
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(0, hi)
    deformed = vtk.vtkActor()
    deformed.SetMapper(mapper)
    deformed.GetProperty().SetInterpolationToPhong()
    deformed.GetProperty().SetAmbient(0.35)
    deformed.GetProperty().SetDiffuse(0.7)

    # The undeformed part: its feature edges (face boundaries and sharp creases).
    edges = vtk.vtkFeatureEdges()
    edges.SetInputData(surface)
    edges.BoundaryEdgesOff()
    edges.NonManifoldEdgesOff()
    edges.FeatureEdgesOn()
    edges.SetFeatureAngle(30)
    edges.ColoringOff()
    edge_mapper = vtk.vtkPolyDataMapper()
    edge_mapper.SetInputConnection(edges.GetOutputPort())
    undeformed = vtk.vtkActor()
    undeformed.SetMapper(edge_mapper)
    undeformed.GetProperty().SetColor(0.3, 0.3, 0.3)
    undeformed.GetProperty().SetLineWidth(1.5)

    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle("von Mises [MPa]")
    bar.SetNumberOfLabels(5)
    bar.SetLabelFormat("%.0f")
    bar.SetOrientationToHorizontal()
    bar.SetPosition(0.25, 0.04)
    bar.SetWidth(0.5)
    bar.SetHeight(0.1)
    lut_mpa = vtk.vtkLookupTable()  # the bar in MPa, the colours the same
    lut_mpa.DeepCopy(lut)
    lut_mpa.SetTableRange(0, hi / 1e6)
    bar.SetLookupTable(lut_mpa)
    for text in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        text.SetColor(0.1, 0.1, 0.1)
        text.SetFontSize(14)
        text.ItalicOff()
        text.ShadowOff()
    bar.UnconstrainedFontSizeOn()

    title = vtk.vtkTextActor()
    title.SetInput(f"immersed analysis of rounded_bracket.step: 2 MPa on the end face, "
                   f"deformation x{SCALE:.0f}")
    title.GetTextProperty().SetColor(0.1, 0.1, 0.1)
    title.GetTextProperty().SetFontSize(16)
    title.SetDisplayPosition(12, 470)

    render_png(png, [deformed, undeformed], [bar, title], size=(800, 500),
               focal_point=(0.03, 0.015, 0.01), position=(0.12, -0.09, 0.08), zoom=1.3)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
