#!/usr/bin/python3
"""Renders the README picture from the VTK output of `isospring demo` (result.vtm).

The demo's cantilever block, deformed by the IGA solution of the tip load (warped by
displacement_tip_down at true scale) and coloured by von Mises stress, over the undeformed
block's outline. Uses Debian's python3-vtk9 (VTK 9.1); it needs an X display, so run it through
scripts/render_readme_image.sh (xvfb-run) on a headless machine.

Usage: render_readme_image.py DEMO_OUT_DIR OUTPUT.png
"""
import sys

import vtk

from vtk_png import render_png


def main(demo_dir, png):
    reader = vtk.vtkXMLMultiBlockDataReader()
    reader.SetFileName(f"{demo_dir}/result.vtm")
    reader.Update()
    blocks = reader.GetOutput()
    grid = None
    for b in range(blocks.GetNumberOfBlocks()):
        if blocks.GetMetaData(b).Get(vtk.vtkCompositeDataSet.NAME()) == "geometry":
            grid = blocks.GetBlock(b)
    if grid is None:
        sys.exit(f"{demo_dir}/result.vtm has no 'geometry' block; run `isospring demo` first")

    grid.GetPointData().SetActiveVectors("displacement_tip_down")
    warp = vtk.vtkWarpVector()
    warp.SetInputData(grid)
    warp.SetScaleFactor(1.0)  # true scale: the tip moves 13.5 mm on a 100 mm block
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputConnection(warp.GetOutputPort())

    stress = "von_mises_tip_down"
    lo, hi = grid.GetPointData().GetArray(stress).GetRange()
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.667, 0.0)  # blue (low) to red (high)
    lut.SetTableRange(lo, hi)
    lut.Build()
    mapper = vtk.vtkDataSetMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(stress)
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(lo, hi)
    deformed = vtk.vtkActor()
    deformed.SetMapper(mapper)
    deformed.GetProperty().SetInterpolationToPhong()
    deformed.GetProperty().SetAmbient(0.35)  # keep the faces turned from the light readable
    deformed.GetProperty().SetDiffuse(0.7)

    outline = vtk.vtkOutlineFilter()
    outline.SetInputData(grid)
    outline_mapper = vtk.vtkPolyDataMapper()
    outline_mapper.SetInputConnection(outline.GetOutputPort())
    undeformed = vtk.vtkActor()
    undeformed.SetMapper(outline_mapper)
    undeformed.GetProperty().SetColor(0.35, 0.35, 0.35)
    undeformed.GetProperty().SetLineWidth(1.5)

    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle("von Mises [Pa]")
    bar.SetNumberOfLabels(4)
    bar.SetLabelFormat("%.0f")
    bar.SetOrientationToHorizontal()
    bar.SetPosition(0.25, 0.04)
    bar.SetWidth(0.5)
    bar.SetHeight(0.1)
    for text in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        text.SetColor(0.1, 0.1, 0.1)
        text.SetFontSize(14)
        text.ItalicOff()
        text.ShadowOff()
    bar.UnconstrainedFontSizeOn()

    title = vtk.vtkTextActor()
    title.SetInput("isospring demo: IGA cantilever under a tip load (true-scale deformation)")
    title.GetTextProperty().SetColor(0.1, 0.1, 0.1)
    title.GetTextProperty().SetFontSize(16)
    title.SetDisplayPosition(12, 370)

    render_png(png, [deformed, undeformed], [bar, title], size=(800, 400),
               focal_point=(0.05, 0.01, 0.0), position=(0.11, -0.17, 0.08), zoom=1.5)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
