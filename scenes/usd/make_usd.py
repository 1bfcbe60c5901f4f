#!/usr/bin/env python3
"""Authors the shipped USD scenes with Pixar's own USD (PyPI `usd-core`). Dev-only: the stages
are committed, so neither rendering nor the tests need Python.

    python3 -m venv /tmp/usd && /tmp/usd/bin/pip install usd-core==26.11
    /tmp/usd/bin/python scenes/usd/make_usd.py

- cornell-box.usda / cornell-box.usdc: the Cornell box of scenes/cornell-box (the same
  triangles, camera and materials) as one stage, written in both file formats;
  scenes/usd/cornell-box.toml gives it the measured spectra.
- glass-plate.usda: the glass plate of scenes/glass-plate as a composed stage: the plate is an
  asset (plate.usda) brought in by a reference, with a variant set `finish` choosing the top
  face's lobe (narrow: GGX alpha 0.02 as in the paper, or polished); Z up, as Blender writes.
"""
import math
import os

from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade

HERE = os.path.dirname(os.path.abspath(__file__))
CORNELL = os.path.join(HERE, "..", "cornell-box")
# quasar's luminance unit: a spectrum of luminance 1 in a TOML scene is 683 x 106.857 cd/m^2
NITS_PER_Y = 683.0 * 106.857


def read_obj(name):
    points, faces = [], []
    for line in open(os.path.join(CORNELL, name)):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            points.append(Gf.Vec3f(*map(float, w[1:4])))
        elif w[0] == "f":
            faces.append([int(i.split("/")[0]) - 1 for i in w[1:]])
    return points, faces


def mesh(stage, at, points, faces, material=None):
    m = UsdGeom.Mesh.Define(stage, at)
    m.CreatePointsAttr(points)
    m.CreateFaceVertexCountsAttr([len(f) for f in faces])
    m.CreateFaceVertexIndicesAttr([i for f in faces for i in f])
    m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    if material is not None:
        UsdShade.MaterialBindingAPI.Apply(m.GetPrim()).Bind(material)
    return m


def preview(stage, at, **inputs):
    mat = UsdShade.Material.Define(stage, at)
    shader = UsdShade.Shader.Define(stage, at + "/Surface")
    shader.CreateIdAttr("UsdPreviewSurface")
    for k, v in inputs.items():
        t = Sdf.ValueTypeNames.Color3f if k.endswith("Color") else Sdf.ValueTypeNames.Float
        shader.CreateInput(k, t).Set(v)
    mat.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return mat


def cornell():
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    stage.GetRootLayer().documentation = (
        "The Cornell box (Cornell Program of Computer Graphics, Cornell Box Data) in metres, written "
        "by scenes/usd/make_usd.py from scenes/cornell-box. The preview surfaces are the mean "
        "reflectances of the measured paints; scenes/usd/cornell-box.toml replaces "
        "them and the light's emission with the measured spectra."
    )
    looks = {
        # mean reflectances (400-700 nm) of the measured tables, as grey-ish sRGB stand-ins
        "White": preview(stage, "/World/Looks/White", diffuseColor=Gf.Vec3f(0.74, 0.74, 0.72), roughness=1.0),
        "Green": preview(stage, "/World/Looks/Green", diffuseColor=Gf.Vec3f(0.12, 0.45, 0.09), roughness=1.0),
        "Red": preview(stage, "/World/Looks/Red", diffuseColor=Gf.Vec3f(0.63, 0.065, 0.05), roughness=1.0),
        # the lamp: the luminance of the published spectrum (light.csv as W/(sr m^2 nm))
        "Light": preview(
            stage, "/World/Looks/Light", diffuseColor=Gf.Vec3f(0.78, 0.78, 0.78), roughness=1.0,
            emissiveColor=Gf.Vec3f(1.2e6, 1.0e6, 0.75e6),
        ),
    }
    for name, obj, look in [
        ("Walls", "walls_white.obj", "White"),
        ("Blocks", "blocks.obj", "White"),
        ("GreenWall", "wall_green.obj", "Green"),
        ("RedWall", "wall_red.obj", "Red"),
        ("Light", "light.obj", "Light"),
    ]:
        p, f = read_obj(obj)
        mesh(stage, "/World/" + name, p, f, looks[look])
    # the published camera: eye (278, 273, -800) mm looking along +z, 35 mm lens on 25 x 25 mm
    cam = UsdGeom.Camera.Define(stage, "/World/Camera")
    cam.CreateFocalLengthAttr(35.0)
    cam.CreateHorizontalApertureAttr(25.0)
    cam.CreateVerticalApertureAttr(25.0)
    cam.AddTranslateOp().Set(Gf.Vec3d(0.278, 0.273, -0.8))
    cam.AddRotateYOp().Set(180.0)
    for ext in ("usda", "usdc"):
        stage.GetRootLayer().Export(os.path.join(HERE, "cornell-box." + ext))


def zup(p):
    """quasar (x, y up, z) -> USD Z-up (x, -z, y)."""
    return Gf.Vec3f(p[0], -p[2], p[1])


def quad(corner, e1, e2):
    c = Gf.Vec3f(*corner)
    a, b = Gf.Vec3f(*e1), Gf.Vec3f(*e2)
    return [zup(c), zup(c + a), zup(c + a + b), zup(c + b)]


def plate_asset():
    """plate.usda: the 0.2 x 0.2 x 0.02 m plate of scenes/glass-plate, 1 mm above z = 0."""
    stage = Usd.Stage.CreateNew(os.path.join(HERE, "plate.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    plate = UsdGeom.Xform.Define(stage, "/Plate")
    stage.SetDefaultPrim(plate.GetPrim())
    # the top's roughness only in the variants: a local opinion would be stronger than theirs
    top = preview(stage, "/Plate/Looks/Top", diffuseColor=Gf.Vec3f(1, 1, 1), opacity=0.0, ior=1.5)
    bottom = preview(stage, "/Plate/Looks/Bottom", diffuseColor=Gf.Vec3f(0.8, 0.8, 0.8), roughness=1.0)
    side = preview(stage, "/Plate/Looks/Side", diffuseColor=Gf.Vec3f(1, 1, 1), opacity=0.0, ior=1.5, roughness=0.0)
    faces = {
        "Top": (top, [(-0.1, 0.021, 0.1), (0.2, 0, 0), (0, 0, -0.2)]),
        "Bottom": (bottom, [(-0.1, 0.001, -0.1), (0.2, 0, 0), (0, 0, 0.2)]),
        "Front": (side, [(-0.1, 0.001, 0.1), (0.2, 0, 0), (0, 0.02, 0)]),
        "Back": (side, [(0.1, 0.001, -0.1), (-0.2, 0, 0), (0, 0.02, 0)]),
        "Right": (side, [(0.1, 0.001, 0.1), (0, 0, -0.2), (0, 0.02, 0)]),
        "Left": (side, [(-0.1, 0.001, -0.1), (0, 0, 0.2), (0, 0.02, 0)]),
    }
    for name, (look, q) in faces.items():
        mesh(stage, "/Plate/" + name, quad(*q), [[0, 1, 2, 3]], look)
    # the top face's finish: the paper's narrow lobe (GGX alpha 0.02 = roughness^2) or polished
    vset = plate.GetPrim().GetVariantSets().AddVariantSet("finish")
    for name, roughness in (("narrow", math.sqrt(0.02)), ("polished", 0.0)):
        vset.AddVariant(name)
        vset.SetVariantSelection(name)
        with vset.GetVariantEditContext():
            shader = UsdShade.Shader.Get(stage, "/Plate/Looks/Top/Surface")
            shader.CreateInput("roughness", Sdf.ValueTypeNames.Float).Set(roughness)
    vset.ClearVariantSelection()
    stage.GetRootLayer().Save()


def look_at(eye, target):
    """A camera transform (camera looks along -Z with +Y up) at eye looking at target, Z up."""
    view = Gf.Matrix4d().SetLookAt(Gf.Vec3d(*eye), Gf.Vec3d(*target), Gf.Vec3d(0, 0, 1))
    return view.GetInverse()


def glass_plate():
    stage = Usd.Stage.CreateNew(os.path.join(HERE, "glass-plate.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    stage.GetRootLayer().documentation = (
        "The glass plate of Zhdanov, Ershov & Voloboy (GraphiCon 2015) as a composed stage: the "
        "plate asset by reference, its top finish by variant. Written by scenes/usd/make_usd.py."
    )
    substrate = preview(stage, "/World/Looks/Substrate", diffuseColor=Gf.Vec3f(0.65, 0.62, 0.55), roughness=1.0)
    mesh(stage, "/World/Substrate", quad((-0.5, 0, 0.5), (1, 0, 0), (0, 0, -1)), [[0, 1, 2, 3]], substrate)
    plate = stage.DefinePrim("/World/Plate")
    plate.GetReferences().AddReference("./plate.usda")
    plate.GetVariantSets().GetVariantSet("finish").SetVariantSelection("narrow")
    # the lamp: 0.12 m square facing down, a 3200 K blackbody of luminance 60 (TOML units)
    lamp = UsdLux.RectLight.Define(stage, "/World/Lamp")
    lamp.CreateWidthAttr(0.12)
    lamp.CreateHeightAttr(0.12)
    lamp.CreateIntensityAttr(60.0 * NITS_PER_Y)
    lamp.CreateEnableColorTemperatureAttr(True)
    lamp.CreateColorTemperatureAttr(3200.0)
    lamp.AddTranslateOp().Set(Gf.Vec3d(-0.14, 0.19, 0.45))  # quasar (-0.14, 0.45, -0.19)
    # RectLight emits along -Z: facing down already in a Z-up stage
    # dim daylight sky: D65 of luminance 0.15 (TOML units)
    sky = UsdLux.DomeLight.Define(stage, "/World/Sky")
    sky.CreateIntensityAttr(0.15 * NITS_PER_Y)
    cam = UsdGeom.Camera.Define(stage, "/World/Camera")
    # 38 degrees vertical on a 4:3 film
    v_ap = 15.0
    cam.CreateVerticalApertureAttr(v_ap)
    cam.CreateHorizontalApertureAttr(v_ap * 4.0 / 3.0)
    cam.CreateFocalLengthAttr(0.5 * v_ap / math.tan(math.radians(19.0)))
    cam.AddTransformOp().Set(look_at(zup((0.26, 0.17, 0.32)), zup((0, 0, 0))))
    stage.GetRootLayer().Save()


if __name__ == "__main__":
    cornell()
    plate_asset()
    glass_plate()
