"""Offscreen VTK rendering to a PNG, shared by the scripts that make the docs' pictures."""
import vtk


def render_png(png, actors, overlays, size, focal_point, position, zoom):
    """Renders `actors` and the 2D `overlays` on white with the camera looking from `position`
    at `focal_point` (z up), then zoomed by `zoom` after fitting the scene, into `png`."""
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    for actor in actors:
        renderer.AddActor(actor)
    for overlay in overlays:
        renderer.AddActor2D(overlay)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(*focal_point)
    camera.SetPosition(*position)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(zoom)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*size)
    window.SetMultiSamples(8)
    window.AddRenderer(renderer)
    window.Render()
    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(png)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()
