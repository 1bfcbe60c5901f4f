#!/usr/bin/env python3
"""Authors the USD fixtures of importers/tests/usd.rs with Pixar's own USD (PyPI `usd-core`), and
writes what Pixar's API computes for them (world-space points, camera fields, light parameters)
to expected.json, the oracle the Rust tests compare the importer against.

Dev-only; the fixtures are committed, so the tests need neither Python nor usd-core:

    python3 -m venv /tmp/usd && /tmp/usd/bin/pip install usd-core==26.11
    /tmp/usd/bin/python importers/tests/usd/make_fixtures.py
"""
import json
import os

from pxr import Gf, Sdf, Usd, UsdGeom, UsdLux, UsdShade, Vt

HERE = os.path.dirname(os.path.abspath(__file__))


def path(name):
    return os.path.join(HERE, name)


def preview_material(stage, at, **inputs):
    mat = UsdShade.Material.Define(stage, at)
    shader = UsdShade.Shader.Define(stage, at + "/Surface")
    shader.CreateIdAttr("UsdPreviewSurface")
    types = {"diffuseColor": Sdf.ValueTypeNames.Color3f, "emissiveColor": Sdf.ValueTypeNames.Color3f}
    for k, v in inputs.items():
        shader.CreateInput(k, types.get(k, Sdf.ValueTypeNames.Float)).Set(v)
    mat.CreateSurfaceOutput().ConnectToSource(shader.ConnectableAPI(), "surface")
    return mat


def scene():
    """scene.usda: meshes with every normal interpolation, xform stacks, a hole, a left-handed
    mesh, a Catmull-Clark mesh, invisible / proxy / inactive prims, a camera, materials."""
    stage = Usd.Stage.CreateNew(path("scene.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    world.AddTranslateOp().Set(Gf.Vec3d(1, 2, 3))
    world.AddRotateYOp().Set(90.0)
    world.AddScaleOp().Set(Gf.Vec3f(2, 2, 2))

    red = preview_material(stage, "/World/Looks/Red", diffuseColor=Gf.Vec3f(0.8, 0.2, 0.1), roughness=0.5, metallic=0.0)
    glass = preview_material(stage, "/World/Looks/Glass", diffuseColor=Gf.Vec3f(1, 1, 1), opacity=0.0, ior=1.5, roughness=0.0)
    lamp = preview_material(stage, "/World/Looks/Lamp", diffuseColor=Gf.Vec3f(0, 0, 0), emissiveColor=Gf.Vec3f(2, 2, 2))

    # a quad with face-varying normals and vertex st; bound to Red
    quad = UsdGeom.Mesh.Define(stage, "/World/Quad")
    quad.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    quad.CreateFaceVertexCountsAttr([4])
    quad.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    quad.CreateNormalsAttr([(0, 0, 1)] * 4)
    quad.SetNormalsInterpolation(UsdGeom.Tokens.faceVarying)
    quad.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    st = UsdGeom.PrimvarsAPI(quad).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex)
    st.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
    UsdShade.MaterialBindingAPI.Apply(quad.GetPrim()).Bind(red)

    # a pentagon (fan) and a quad with a hole; uniform normals; own transform with !invert!
    holed = UsdGeom.Mesh.Define(stage, "/World/Holed")
    holed.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (2, 0, 0), (2, 1, 0), (1, 1, 0), (0, 1, 0), (1.5, 1.5, 0)])
    holed.CreateFaceVertexCountsAttr([4, 5])
    holed.CreateFaceVertexIndicesAttr([0, 1, 4, 5, 1, 2, 3, 6, 4])
    holed.CreateHoleIndicesAttr([0])
    holed.CreateNormalsAttr([(0, 0, 1), (0, 0, 1)])
    holed.SetNormalsInterpolation(UsdGeom.Tokens.uniform)
    holed.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    op = holed.AddTranslateOp(opSuffix="pivot")
    op.Set(Gf.Vec3d(0, 0, 5))
    holed.AddRotateZOp().Set(30.0)
    holed.AddTranslateOp(opSuffix="pivot", isInverseOp=True)
    UsdShade.MaterialBindingAPI.Apply(holed.GetPrim()).Bind(glass)

    # left-handed triangle, Catmull-Clark by default (no subdivisionScheme authored), a lamp
    lh = UsdGeom.Mesh.Define(stage, "/World/LeftHanded")
    lh.CreatePointsAttr([(0, 0, 1), (1, 0, 1), (0, 1, 1)])
    lh.CreateFaceVertexCountsAttr([3])
    lh.CreateFaceVertexIndicesAttr([0, 1, 2])
    lh.CreateOrientationAttr(UsdGeom.Tokens.leftHanded)
    UsdShade.MaterialBindingAPI.Apply(lh.GetPrim()).Bind(lamp)

    # a group that resets the transform stack and holds a vertex-normal triangle
    group = UsdGeom.Xform.Define(stage, "/World/Reset")
    group.GetPrim().CreateAttribute("xformOpOrder", Sdf.ValueTypeNames.TokenArray, variability=Sdf.VariabilityUniform)
    group.SetResetXformStack(True)
    group.AddTranslateOp().Set(Gf.Vec3d(0, 10, 0))
    tri = UsdGeom.Mesh.Define(stage, "/World/Reset/Tri")
    tri.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 0, -1)])
    tri.CreateFaceVertexCountsAttr([3])
    tri.CreateFaceVertexIndicesAttr([0, 1, 2])
    tri.CreateNormalsAttr([(0, 1, 0)] * 3)
    tri.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
    tri.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    # a time-sampled translate (read at the default time code, which here has no default value:
    # the earliest sample applies)
    tri.AddTranslateOp().Set(Gf.Vec3d(0, 0, 0), 1.0)
    tri.GetPrim().GetAttribute("xformOp:translate").Set(Gf.Vec3d(0, 0, 7), 2.0)

    # two quads split by a materialBind GeomSubset: face 1 is Red, the rest the mesh's Glass
    split = UsdGeom.Mesh.Define(stage, "/World/Split")
    split.CreatePointsAttr([(0, 0, 2), (1, 0, 2), (1, 1, 2), (0, 1, 2), (2, 0, 2), (2, 1, 2)])
    split.CreateFaceVertexCountsAttr([4, 4])
    split.CreateFaceVertexIndicesAttr([0, 1, 2, 3, 1, 4, 5, 2])
    split.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    UsdShade.MaterialBindingAPI.Apply(split.GetPrim()).Bind(glass)
    subset = UsdShade.MaterialBindingAPI(split).CreateMaterialBindSubset("right", Vt.IntArray([1]), UsdGeom.Tokens.face)
    UsdShade.MaterialBindingAPI.Apply(subset.GetPrim()).Bind(red)

    # skipped: invisible, proxy purpose, inactive
    for name, how in [("Hidden", "invisible"), ("Proxy", "proxy"), ("Inactive", "inactive")]:
        m = UsdGeom.Mesh.Define(stage, "/World/" + name)
        m.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
        m.CreateFaceVertexCountsAttr([3])
        m.CreateFaceVertexIndicesAttr([0, 1, 2])
        if how == "invisible":
            m.CreateVisibilityAttr(UsdGeom.Tokens.invisible)
        elif how == "proxy":
            m.CreatePurposeAttr(UsdGeom.Tokens.proxy)
        else:
            m.GetPrim().SetActive(False)

    cam = UsdGeom.Camera.Define(stage, "/World/Cam")
    cam.AddTranslateOp().Set(Gf.Vec3d(0, 0, 10))
    cam.CreateFocalLengthAttr(50.0)
    cam.CreateHorizontalApertureAttr(36.0)
    cam.CreateVerticalApertureAttr(24.0)
    stage.GetRootLayer().Save()
    return stage


def lights():
    """lights.usda: one prim per UsdLux light, Z up, centimetres."""
    stage = Usd.Stage.CreateNew(path("lights.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 0.01)
    UsdGeom.Xform.Define(stage, "/L")
    rect = UsdLux.RectLight.Define(stage, "/L/Rect")
    rect.CreateWidthAttr(20.0)
    rect.CreateHeightAttr(10.0)
    rect.CreateIntensityAttr(100.0)
    rect.CreateExposureAttr(1.0)
    rect.CreateColorAttr(Gf.Vec3f(1, 0.5, 0.25))
    rect.AddTranslateOp().Set(Gf.Vec3d(0, 0, 200))
    disk = UsdLux.DiskLight.Define(stage, "/L/Disk")
    disk.CreateRadiusAttr(5.0)
    disk.CreateIntensityAttr(50.0)
    disk.CreateNormalizeAttr(True)
    sphere = UsdLux.SphereLight.Define(stage, "/L/Sphere")
    sphere.CreateRadiusAttr(2.0)
    sphere.CreateIntensityAttr(10.0)
    point = UsdLux.SphereLight.Define(stage, "/L/Point")
    point.CreateRadiusAttr(1.0)
    point.CreateTreatAsPointAttr(True)
    point.CreateIntensityAttr(1000.0)
    point.AddTranslateOp().Set(Gf.Vec3d(0, 0, 100))
    spot = UsdLux.SphereLight.Define(stage, "/L/Spot")
    spot.CreateTreatAsPointAttr(True)
    spot.CreateRadiusAttr(0.5)
    spot.CreateIntensityAttr(400.0)
    shaping = UsdLux.ShapingAPI.Apply(spot.GetPrim())
    shaping.CreateShapingConeAngleAttr(30.0)
    shaping.CreateShapingConeSoftnessAttr(0.5)
    sun = UsdLux.DistantLight.Define(stage, "/L/Sun")
    sun.CreateIntensityAttr(2000.0)
    sun.CreateAngleAttr(0.53)
    sun.AddRotateXOp().Set(-45.0)
    dome = UsdLux.DomeLight.Define(stage, "/L/Dome")
    dome.CreateIntensityAttr(0.5)
    cyl = UsdLux.CylinderLight.Define(stage, "/L/Cylinder")
    cyl.CreateLengthAttr(30.0)
    cyl.CreateRadiusAttr(1.0)
    cyl.CreateIntensityAttr(5.0)
    ground = UsdGeom.Mesh.Define(stage, "/L/Ground")
    ground.CreatePointsAttr([(-100, -100, 0), (100, -100, 0), (100, 100, 0), (-100, 100, 0)])
    ground.CreateFaceVertexCountsAttr([4])
    ground.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    ground.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    stage.GetRootLayer().Save()
    return stage


def composed():
    """composed.usdc (binary) referencing asset.usda, with a variant selection and a payload."""
    asset = Usd.Stage.CreateNew(path("asset.usda"))
    root = UsdGeom.Xform.Define(asset, "/Asset")
    asset.SetDefaultPrim(root.GetPrim())
    vset = root.GetPrim().GetVariantSets().AddVariantSet("size")
    for name, s in [("small", 1.0), ("large", 3.0)]:
        vset.AddVariant(name)
        vset.SetVariantSelection(name)
        with vset.GetVariantEditContext():
            m = UsdGeom.Mesh.Define(asset, "/Asset/Body")
            m.CreatePointsAttr([(0, 0, 0), (s, 0, 0), (0, s, 0)])
            m.CreateFaceVertexCountsAttr([3])
            m.CreateFaceVertexIndicesAttr([0, 1, 2])
            m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    vset.SetVariantSelection("small")
    asset.GetRootLayer().Save()
    stage = Usd.Stage.CreateNew(path("composed.usdc"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    a = stage.DefinePrim("/A")
    a.GetReferences().AddReference("./asset.usda")
    a.GetVariantSets().GetVariantSet("size").SetVariantSelection("large")
    b = UsdGeom.Xform.Define(stage, "/B")
    b.AddTranslateOp().Set(Gf.Vec3d(5, 0, 0))
    b.GetPrim().GetPayloads().AddPayload("./asset.usda")
    stage.GetRootLayer().Save()
    return stage


def expected(stage, file):
    """What Pixar's USD computes for `stage`: per rendered mesh its world points (after the up
    axis and units are applied by quasar: not here), triangles after holes, and the camera."""
    cache = UsdGeom.XformCache(Usd.TimeCode.EarliestTime())
    out = {"file": file, "meters_per_unit": UsdGeom.GetStageMetersPerUnit(stage),
           "up_axis": str(UsdGeom.GetStageUpAxis(stage)), "meshes": {}, "cameras": {}, "lights": {}}
    for prim in stage.Traverse():
        img = UsdGeom.Imageable(prim)
        if prim.IsA(UsdGeom.Mesh):
            if img.ComputeVisibility() == UsdGeom.Tokens.invisible or img.ComputePurpose() not in (UsdGeom.Tokens.default_, UsdGeom.Tokens.render):
                continue
            mesh = UsdGeom.Mesh(prim)
            m = cache.GetLocalToWorldTransform(prim)
            pts = [list(m.Transform(Gf.Vec3d(p))) for p in mesh.GetPointsAttr().Get(Usd.TimeCode.EarliestTime())]
            counts = list(mesh.GetFaceVertexCountsAttr().Get())
            holes = set(mesh.GetHoleIndicesAttr().Get() or [])
            tris = sum(c - 2 for i, c in enumerate(counts) if i not in holes)
            entry = {"world_points": pts, "triangles": tris, "material": str(UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()[0].GetPath())}
            subsets = {}
            for sub in UsdShade.MaterialBindingAPI(prim).GetMaterialBindSubsets():
                faces = list(sub.GetIndicesAttr().Get())
                subsets[str(sub.GetPath())] = {
                    "material": str(UsdShade.MaterialBindingAPI(sub.GetPrim()).ComputeBoundMaterial()[0].GetPath()),
                    "triangles": sum(counts[f] - 2 for f in faces if f not in holes),
                }
            if subsets:
                entry["subsets"] = subsets
            out["meshes"][str(prim.GetPath())] = entry
        elif prim.IsA(UsdGeom.Camera):
            cam = UsdGeom.Camera(prim).GetCamera(Usd.TimeCode.EarliestTime())
            m = cache.GetLocalToWorldTransform(prim)
            out["cameras"][str(prim.GetPath())] = {
                "position": list(m.Transform(Gf.Vec3d(0, 0, 0))),
                "forward": list(m.TransformDir(Gf.Vec3d(0, 0, -1)).GetNormalized()),
                "horizontal_fov_deg": cam.GetFieldOfView(Gf.Camera.FOVHorizontal),
                "vertical_fov_deg": cam.GetFieldOfView(Gf.Camera.FOVVertical),
            }
        elif prim.HasAPI(UsdLux.LightAPI):
            light = UsdLux.LightAPI(prim)
            m = cache.GetLocalToWorldTransform(prim)
            out["lights"][str(prim.GetPath())] = {
                "type": str(prim.GetTypeName()),
                "position": list(m.Transform(Gf.Vec3d(0, 0, 0))),
                "axis_minus_z": list(m.TransformDir(Gf.Vec3d(0, 0, -1)).GetNormalized()),
                "intensity": light.GetIntensityAttr().Get(),
                "exposure": light.GetExposureAttr().Get(),
                "color": list(light.GetColorAttr().Get()),
                "normalize": light.GetNormalizeAttr().Get(),
            }
    return out


if __name__ == "__main__":
    result = [expected(scene(), "scene.usda"), expected(lights(), "lights.usda"), expected(composed(), "composed.usdc")]
    with open(path("expected.json"), "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)
        f.write("\n")
    print("wrote", ", ".join(r["file"] for r in result), "and expected.json")
