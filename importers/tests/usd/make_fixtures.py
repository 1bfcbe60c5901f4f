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


def instanced():
    """instanced.usda: three instanceable references to instanced_asset.usda (two meshes each)
    and a ground, and instanced_flat.usdc, the same stage after UsdStage.Flatten(), which writes
    the prototype as a root `over` prim (its specifier left to Sdf's fallback, `over`, in the
    binary file) that the instances reference. Pixar draws the same meshes from both."""
    asset = Usd.Stage.CreateNew(path("instanced_asset.usda"))
    UsdGeom.SetStageUpAxis(asset, UsdGeom.Tokens.y)
    root = UsdGeom.Xform.Define(asset, "/Asset")
    asset.SetDefaultPrim(root.GetPrim())
    for i, name in enumerate(["A", "B"]):
        m = UsdGeom.Mesh.Define(asset, f"/Asset/{name}")
        m.CreatePointsAttr([(i, 0, 0), (i + 1, 0, 0), (i + 1, 1, 0), (i, 1, 0)])
        m.CreateFaceVertexCountsAttr([4])
        m.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
        m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    asset.GetRootLayer().Save()
    stage = Usd.Stage.CreateNew(path("instanced.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.Xform.Define(stage, "/World")
    for k in range(3):
        x = UsdGeom.Xform.Define(stage, f"/World/inst{k}")
        x.AddTranslateOp().Set(Gf.Vec3d(3 * (k + 1), 0, 0))
        x.GetPrim().GetReferences().AddReference("./instanced_asset.usda")
        x.GetPrim().SetInstanceable(True)
    g = UsdGeom.Mesh.Define(stage, "/World/ground")
    g.CreatePointsAttr([(-5, 0, -5), (5, 0, -5), (5, 0, 5), (-5, 0, 5)])
    g.CreateFaceVertexCountsAttr([4])
    g.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    g.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    stage.GetRootLayer().Save()
    stage.Flatten().Export(path("instanced_flat.usdc"))
    counts = {}
    for name in ["instanced.usda", "instanced_flat.usdc"]:
        st = Usd.Stage.Open(path(name))
        meshes = [p for p in Usd.PrimRange(st.GetPseudoRoot(), Usd.TraverseInstanceProxies()) if p.IsA(UsdGeom.Mesh)]
        tris = sum(sum(c - 2 for c in UsdGeom.Mesh(p).GetFaceVertexCountsAttr().Get()) for p in meshes)
        counts[name] = {"meshes": len(meshes), "triangles": tris}
    return {"file": "instanced.usda", "drawn": counts}


def shapes():
    """shapes.usda: every implicit shape (schema defaults and authored sizes, each axis), a
    PointInstancer (two prototypes under it, orientations, scales, an invisible id), and a mesh
    with a time-sampled translation (for --time-code)."""
    stage = Usd.Stage.CreateNew(path("shapes.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    UsdGeom.Cube.Define(stage, "/World/CubeDefault")
    c = UsdGeom.Cube.Define(stage, "/World/Cube")
    c.CreateSizeAttr(0.5)
    c.AddTranslateOp().Set(Gf.Vec3d(3, 0, 0))
    c.AddScaleOp().Set(Gf.Vec3f(1, 2, 3))
    UsdGeom.Sphere.Define(stage, "/World/Sphere").CreateRadiusAttr(0.25)
    for ax in "XYZ":
        cy = UsdGeom.Cylinder.Define(stage, "/World/Cylinder" + ax)
        cy.CreateAxisAttr(ax)
        cy.CreateRadiusAttr(0.2)
        cy.CreateHeightAttr(1.5)
        cy.AddTranslateOp().Set(Gf.Vec3d(0, 5, 0))
        co = UsdGeom.Cone.Define(stage, "/World/Cone" + ax)
        co.CreateAxisAttr(ax)
        co.AddTranslateOp().Set(Gf.Vec3d(-5, 0, 0))
        ca = UsdGeom.Capsule.Define(stage, "/World/Capsule" + ax)
        ca.CreateAxisAttr(ax)
        ca.CreateHeightAttr(2.0)
        pl = UsdGeom.Plane.Define(stage, "/World/Plane" + ax)
        pl.CreateAxisAttr(ax)
        pl.CreateWidthAttr(2.0)
        pl.CreateLengthAttr(6.0)
    UsdGeom.Capsule.Define(stage, "/World/CapsuleDefault")
    # the schemas with two radii (USD 23.11): defaults, and tapered along each axis
    UsdGeom.Cylinder_1.Define(stage, "/World/Cylinder1Default")
    UsdGeom.Capsule_1.Define(stage, "/World/Capsule1Default")
    for k, ax in enumerate("XYZ"):
        cy = UsdGeom.Cylinder_1.Define(stage, "/World/Cylinder1" + ax)
        cy.CreateAxisAttr(ax)
        cy.CreateRadiusBottomAttr(0.4)
        cy.CreateRadiusTopAttr(0.1)
        cy.CreateHeightAttr(1.0)
        cy.AddTranslateOp().Set(Gf.Vec3d(8, 2 * k, 0))
        ca = UsdGeom.Capsule_1.Define(stage, "/World/Capsule1" + ax)
        ca.CreateAxisAttr(ax)
        ca.CreateRadiusBottomAttr(0.5)
        ca.CreateRadiusTopAttr(0.2)
        ca.CreateHeightAttr(1.0)
        ca.AddTranslateOp().Set(Gf.Vec3d(-8, 2 * k, 0))
    rot = UsdGeom.Cone.Define(stage, "/World/ConeTurned")
    rot.AddRotateZOp().Set(90.0)

    inst = UsdGeom.PointInstancer.Define(stage, "/World/Forest")
    inst.AddTranslateOp().Set(Gf.Vec3d(0, 0, -10))
    UsdGeom.Scope.Define(stage, "/World/Forest/Prototypes")
    tri = UsdGeom.Mesh.Define(stage, "/World/Forest/Prototypes/Tri")
    tri.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    tri.CreateFaceVertexCountsAttr([3])
    tri.CreateFaceVertexIndicesAttr([0, 1, 2])
    tri.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    tri.AddTranslateOp().Set(Gf.Vec3d(0, 0.5, 0))  # the prototype root's own transform counts
    tree = UsdGeom.Xform.Define(stage, "/World/Forest/Prototypes/Tree")
    tree.AddScaleOp().Set(Gf.Vec3f(2, 2, 2))
    trunk = UsdGeom.Mesh.Define(stage, "/World/Forest/Prototypes/Tree/Trunk")
    trunk.CreatePointsAttr([(0, 0, 0), (0.1, 0, 0), (0.1, 1, 0), (0, 1, 0)])
    trunk.CreateFaceVertexCountsAttr([4])
    trunk.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    trunk.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    trunk.AddRotateYOp().Set(30.0)
    inst.CreatePrototypesRel().SetTargets([tri.GetPath(), tree.GetPath()])
    inst.CreateProtoIndicesAttr([0, 1, 1, 0])
    inst.CreatePositionsAttr([(0, 0, 0), (2, 0, 0), (4, 0, 1), (6, 1, 0)])
    inst.CreateOrientationsAttr([Gf.Quath(1, 0, 0, 0), Gf.Quath(0.7071068, 0, 0.7071068, 0),
                                 Gf.Quath(0.5, 0.5, 0.5, 0.5), Gf.Quath(0.9238795, 0, 0, 0.3826834)])
    inst.CreateScalesAttr([(1, 1, 1), (1, 2, 1), (0.5, 0.5, 0.5), (3, 1, 1)])
    inst.CreateIdsAttr([10, 11, 12, 13])
    inst.CreateInvisibleIdsAttr([12])

    moving = UsdGeom.Mesh.Define(stage, "/World/Moving")
    moving.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    moving.CreateFaceVertexCountsAttr([3])
    moving.CreateFaceVertexIndicesAttr([0, 1, 2])
    moving.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    op = moving.AddTranslateOp()
    op.Set(Gf.Vec3d(0, 0, 0), 1.0)
    op.Set(Gf.Vec3d(9, 0, 0), 10.0)
    stage.GetRootLayer().Save()
    return stage


def write_png(name, width, height, texels):
    """An 8-bit RGBA PNG of `texels` (rows top to bottom), without an imaging library."""
    import struct
    import zlib
    raw = b"".join(b"\x00" + bytes(c for t in texels[y * width:(y + 1) * width] for c in t) for y in range(height))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
    os.makedirs(os.path.dirname(path(name)), exist_ok=True)
    with open(path(name), "wb") as f:
        f.write(png)


def uv_texture(stage, at, file, output, **inputs):
    tex = UsdShade.Shader.Define(stage, at)
    tex.CreateIdAttr("UsdUVTexture")
    if file is not None:
        tex.CreateInput("file", Sdf.ValueTypeNames.Asset).Set(file)
    types = {"wrapS": Sdf.ValueTypeNames.Token, "wrapT": Sdf.ValueTypeNames.Token,
             "sourceColorSpace": Sdf.ValueTypeNames.Token, "scale": Sdf.ValueTypeNames.Float4,
             "bias": Sdf.ValueTypeNames.Float4}
    for k, v in inputs.items():
        tex.CreateInput(k, types[k]).Set(v)
    tex.CreateOutput(output, Sdf.ValueTypeNames.Float3 if output == "rgb" else Sdf.ValueTypeNames.Float)
    return tex


def textures():
    """textures.usda: UsdUVTexture inputs: a base colour through UsdTransform2d with wrap modes
    and a scale, separate roughness (r) and metallic (g) images packed by the importer, a
    normal map with the standard scale/bias, a file given by a Material interface input, and
    a textured quad whose st runs over the image."""
    write_png("tex/albedo.png", 4, 2, [(255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255), (255, 255, 255, 255),
                                       (10, 20, 30, 255), (40, 50, 60, 255), (70, 80, 90, 255), (0, 0, 0, 255)])
    write_png("tex/rough.png", 2, 2, [(200, 0, 0, 255), (100, 0, 0, 255), (50, 0, 0, 255), (0, 0, 0, 255)])
    write_png("tex/metal.png", 1, 1, [(0, 77, 0, 255)])
    write_png("tex/normal.png", 1, 1, [(128, 128, 255, 255)])
    stage = Usd.Stage.CreateNew(path("textures.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    mat = UsdShade.Material.Define(stage, "/World/Looks/Painted")
    surf = UsdShade.Shader.Define(stage, "/World/Looks/Painted/Surface")
    surf.CreateIdAttr("UsdPreviewSurface")
    reader = UsdShade.Shader.Define(stage, "/World/Looks/Painted/St")
    reader.CreateIdAttr("UsdPrimvarReader_float2")
    reader.CreateInput("varname", Sdf.ValueTypeNames.Token).Set("st")
    reader.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    xf = UsdShade.Shader.Define(stage, "/World/Looks/Painted/Place")
    xf.CreateIdAttr("UsdTransform2d")
    xf.CreateInput("in", Sdf.ValueTypeNames.Float2).ConnectToSource(reader.ConnectableAPI(), "result")
    xf.CreateInput("scale", Sdf.ValueTypeNames.Float2).Set(Gf.Vec2f(2, 1))
    xf.CreateInput("rotation", Sdf.ValueTypeNames.Float).Set(90.0)
    xf.CreateInput("translation", Sdf.ValueTypeNames.Float2).Set(Gf.Vec2f(0.5, 0.25))
    xf.CreateOutput("result", Sdf.ValueTypeNames.Float2)
    # the albedo's file comes from the material's interface
    mat.CreateInput("albedoFile", Sdf.ValueTypeNames.Asset).Set("./tex/albedo.png")
    albedo = uv_texture(stage, "/World/Looks/Painted/Albedo", None, "rgb", wrapS="clamp", wrapT="mirror",
                        scale=Gf.Vec4f(0.5, 0.5, 0.5, 1))
    albedo.CreateInput("file", Sdf.ValueTypeNames.Asset).ConnectToSource(mat.GetInput("albedoFile"))
    albedo.CreateInput("st", Sdf.ValueTypeNames.Float2).ConnectToSource(xf.ConnectableAPI(), "result")
    rough = uv_texture(stage, "/World/Looks/Painted/Rough", "./tex/rough.png", "r", sourceColorSpace="raw")
    metal = uv_texture(stage, "/World/Looks/Painted/Metal", "./tex/metal.png", "g", sourceColorSpace="raw",
                       scale=Gf.Vec4f(1, 0.5, 1, 1))
    normal = uv_texture(stage, "/World/Looks/Painted/Normal", "./tex/normal.png", "rgb", sourceColorSpace="raw",
                        scale=Gf.Vec4f(2, 2, 2, 1), bias=Gf.Vec4f(-1, -1, -1, 0))
    surf.CreateInput("diffuseColor", Sdf.ValueTypeNames.Color3f).ConnectToSource(albedo.ConnectableAPI(), "rgb")
    surf.CreateInput("roughness", Sdf.ValueTypeNames.Float).ConnectToSource(rough.ConnectableAPI(), "r")
    surf.CreateInput("metallic", Sdf.ValueTypeNames.Float).ConnectToSource(metal.ConnectableAPI(), "g")
    surf.CreateInput("normal", Sdf.ValueTypeNames.Normal3f).ConnectToSource(normal.ConnectableAPI(), "rgb")
    mat.CreateSurfaceOutput().ConnectToSource(surf.ConnectableAPI(), "surface")
    quad = UsdGeom.Mesh.Define(stage, "/World/Quad")
    quad.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    quad.CreateFaceVertexCountsAttr([4])
    quad.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    quad.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    st = UsdGeom.PrimvarsAPI(quad).CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.vertex)
    st.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
    UsdShade.MaterialBindingAPI.Apply(quad.GetPrim()).Bind(mat)
    stage.GetRootLayer().Save()
    return stage


def expected_textures(stage):
    """Per UsdUVTexture of the material: the file Pixar resolves (relative to the fixture
    folder), the output read, wrap modes, scale and bias as composed."""
    out = {"file": "textures.usda", "textures": {}}
    for prim in stage.Traverse():
        sh = UsdShade.Shader(prim)
        if not sh or sh.GetIdAttr().Get() != "UsdUVTexture":
            continue
        f = sh.GetInput("file")
        src = f.GetValueProducingAttributes()[0] if f.HasConnectedSource() else f.GetAttr()
        resolved = src.Get().resolvedPath
        def get(name, default):
            i = sh.GetInput(name)
            return i.Get() if i and i.Get() is not None else default
        out["textures"][str(prim.GetPath())] = {
            "file": os.path.relpath(resolved, HERE),
            "wrapS": get("wrapS", "useMetadata"),
            "wrapT": get("wrapT", "useMetadata"),
            "scale": list(get("scale", Gf.Vec4f(1, 1, 1, 1))),
            "bias": list(get("bias", Gf.Vec4f(0, 0, 0, 0))),
        }
    return out


def usdz():
    """textures.usdz: textures.usda and its images packaged by Pixar's UsdUtils (the images become
    package entries, resolved as `textures.usdz[tex/albedo.png]`)."""
    from pxr import UsdUtils
    out = path("textures.usdz")
    if os.path.exists(out):
        os.remove(out)
    assert UsdUtils.CreateNewUsdzPackage(Sdf.AssetPath(path("textures.usda")), out)
    stage = Usd.Stage.Open(out)
    result = expected_textures(stage)
    result["file"] = "textures.usdz"
    return result


def expected_shapes(stage):
    """Pixar's world-space bounds of each implicit shape, the world points of every visible
    PointInstancer instance's meshes (in instance order), and the moving mesh at two times."""
    out = {"file": "shapes.usda", "shapes": {}, "instances": [], "moving": {}}
    bbox = UsdGeom.BBoxCache(Usd.TimeCode.EarliestTime(), [UsdGeom.Tokens.default_, UsdGeom.Tokens.render])
    for prim in stage.Traverse():
        if prim.IsA(UsdGeom.Gprim) and not prim.IsA(UsdGeom.Mesh):
            r = bbox.ComputeWorldBound(prim).ComputeAlignedRange()
            out["shapes"][str(prim.GetPath())] = {"type": str(prim.GetTypeName()), "min": list(r.GetMin()), "max": list(r.GetMax())}
    inst = UsdGeom.PointInstancer(stage.GetPrimAtPath("/World/Forest"))
    t = Usd.TimeCode.EarliestTime()
    xforms = inst.ComputeInstanceTransformsAtTime(t, t)
    # Pixar's transforms are of the visible instances only (invisibleIds masked out)
    world = UsdGeom.XformCache(t).GetLocalToWorldTransform(inst.GetPrim())
    protos = inst.GetPrototypesRel().GetTargets()
    ids = inst.GetIdsAttr().Get()
    invisible = set(inst.GetInvisibleIdsAttr().Get())
    cache = UsdGeom.XformCache(t)
    visible = [pi for k, pi in enumerate(inst.GetProtoIndicesAttr().Get()) if ids[k] not in invisible]
    assert len(visible) == len(xforms)
    for k, pi in enumerate(visible):
        root = stage.GetPrimAtPath(protos[pi])
        for prim in Usd.PrimRange(root):
            if not prim.IsA(UsdGeom.Mesh):
                continue
            # the mesh's transforms below the prototype root, then the instance's (which holds the root's)
            rel = Gf.Matrix4d(1) if prim == root else cache.ComputeRelativeTransform(prim, root)[0]
            m = rel * xforms[k] * world
            pts = [list(m.Transform(Gf.Vec3d(p))) for p in UsdGeom.Mesh(prim).GetPointsAttr().Get()]
            out["instances"].append({"mesh": str(prim.GetPath()), "world_points": pts})
    moving = stage.GetPrimAtPath("/World/Moving")
    for key, time in (("earliest", Usd.TimeCode.EarliestTime()), ("5.5", Usd.TimeCode(5.5))):
        m = UsdGeom.XformCache(time).GetLocalToWorldTransform(moving)
        out["moving"][key] = list(m.Transform(Gf.Vec3d(0, 0, 0)))
    return out


def arcs():
    """arcs.usda: the composition arcs a DCC export carries besides references: a class prim
    inherited by two prims (its child mesh drawn under each, one overriding a point), a prim
    specializing a class (its base's points, then its own opinion on top), and an animated
    asset referenced with a layer offset (offset 10, scale 2), read at time code 30 (the asset's
    time 10). The classes themselves are not drawn."""
    anim = Usd.Stage.CreateNew(path("arcs_anim.usda"))
    root = UsdGeom.Xform.Define(anim, "/Anim")
    anim.SetDefaultPrim(root.GetPrim())
    op = root.AddTranslateOp()
    op.Set(Gf.Vec3d(0, 0, 0), 0)
    op.Set(Gf.Vec3d(4, 0, 0), 20)
    m = UsdGeom.Mesh.Define(anim, "/Anim/Geo")
    m.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    m.CreateFaceVertexCountsAttr([3])
    m.CreateFaceVertexIndicesAttr([0, 1, 2])
    m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    anim.GetRootLayer().Save()
    stage = Usd.Stage.CreateNew(path("arcs.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    cls = stage.CreateClassPrim("/_class_Tri")
    geo = UsdGeom.Mesh.Define(stage, "/_class_Tri/Geo")
    geo.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    geo.CreateFaceVertexCountsAttr([3])
    geo.CreateFaceVertexIndicesAttr([0, 1, 2])
    geo.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    UsdGeom.Xform.Define(stage, "/World")
    for k in range(2):
        t = UsdGeom.Xform.Define(stage, f"/World/T{k}")
        t.GetPrim().GetInherits().AddInherit(cls.GetPath())
        t.AddTranslateOp().Set(Gf.Vec3d(0, 0, 2 * (k + 1)))
    # a local opinion over the inherited one
    UsdGeom.Mesh(stage.OverridePrim("/World/T1/Geo")).CreatePointsAttr([(0, 0, 0), (2, 0, 0), (0, 2, 0)])
    base = stage.CreateClassPrim("/_base_Quad")
    UsdGeom.Mesh.Define(stage, "/_base_Quad")
    q = UsdGeom.Mesh(base)
    q.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])
    q.CreateFaceVertexCountsAttr([4])
    q.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    q.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    stage.GetPrimAtPath("/_base_Quad").SetSpecifier(Sdf.SpecifierClass)
    s1 = stage.DefinePrim("/World/S1", "Mesh")
    s1.GetSpecializes().AddSpecialize("/_base_Quad")
    UsdGeom.Xformable(s1).AddTranslateOp().Set(Gf.Vec3d(5, 0, 0))
    a = stage.DefinePrim("/World/A")
    a.GetReferences().AddReference("./arcs_anim.usda", layerOffset=Sdf.LayerOffset(10, 2))
    stage.GetRootLayer().Save()
    return stage


def bindings():
    """bindings.usda: material bindings resolved as Pixar's ComputeBoundMaterial for the `full`
    (render) purpose does: a parent's strongerThanDescendants binding over its child's own, a
    full-purpose binding over an all-purpose one, a preview-purpose binding ignored, and
    bindings through a collection: members with and without MaterialBindingAPI, one below an
    included Xform, one with its own direct binding, and a mesh outside it that gets the owner's
    direct binding."""
    stage = Usd.Stage.CreateNew(path("bindings.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    mats = {n: preview_material(stage, f"/Looks/{n}", diffuseColor=c)
            for n, c in [("Red", (0.8, 0.1, 0.1)), ("Green", (0.1, 0.8, 0.1)), ("Blue", (0.1, 0.1, 0.8))]}

    def tri(at, x):
        m = UsdGeom.Mesh.Define(stage, at)
        m.CreatePointsAttr([(x, 0, 0), (x + 1, 0, 0), (x, 1, 0)])
        m.CreateFaceVertexCountsAttr([3])
        m.CreateFaceVertexIndicesAttr([0, 1, 2])
        m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        return m.GetPrim()

    UsdGeom.Xform.Define(stage, "/World")
    strong = UsdGeom.Xform.Define(stage, "/World/Strong").GetPrim()
    child = tri("/World/Strong/Child", 0)
    UsdShade.MaterialBindingAPI.Apply(strong).Bind(mats["Red"], bindingStrength=UsdShade.Tokens.strongerThanDescendants)
    UsdShade.MaterialBindingAPI.Apply(child).Bind(mats["Green"])
    purpose = tri("/World/Purpose", 2)
    api = UsdShade.MaterialBindingAPI.Apply(purpose)
    api.Bind(mats["Red"])
    api.Bind(mats["Blue"], materialPurpose=UsdShade.Tokens.full)
    preview = tri("/World/Preview", 4)
    api = UsdShade.MaterialBindingAPI.Apply(preview)
    api.Bind(mats["Green"])
    api.Bind(mats["Red"], materialPurpose=UsdShade.Tokens.preview)
    coll = UsdGeom.Xform.Define(stage, "/World/Coll").GetPrim()
    # one member carries MaterialBindingAPI (without a binding of its own), the others do not
    # (a collection's members need not: quasar resolves collections itself, openusd 0.6 did so
    # only for prims with the API); a member below an included Xform is in by expandPrims; a
    # member with a direct binding of its own keeps it (the closest prim's binding wins); a
    # direct binding on the collection's owner loses to the collection binding there
    UsdShade.MaterialBindingAPI.Apply(tri("/World/Coll/In", 6))
    tri("/World/Coll/Out", 8)
    tri("/World/Coll/Bare", 10)
    UsdGeom.Xform.Define(stage, "/World/Coll/Group")
    tri("/World/Coll/Group/Deep", 12)
    own = tri("/World/Coll/Own", 14)
    UsdShade.MaterialBindingAPI.Apply(own).Bind(mats["Green"])
    c = Usd.CollectionAPI.Apply(coll, "glass")
    for member in ["/World/Coll/In", "/World/Coll/Bare", "/World/Coll/Group", "/World/Coll/Own"]:
        c.CreateIncludesRel().AddTarget(member)
    api = UsdShade.MaterialBindingAPI.Apply(coll)
    api.Bind(c, mats["Blue"], "glass")
    api.Bind(mats["Red"])
    stage.GetRootLayer().Save()
    return stage


def camera_mm():
    """camera_mm.usda: a CAD-style stage in millimetres with Z up: a 35 mm lens on a 36 x 24 mm
    back, placed 2 m away by a translation and a rotateXYZ, looking at a 1 m square."""
    stage = Usd.Stage.CreateNew(path("camera_mm.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 0.001)
    UsdGeom.Xform.Define(stage, "/World")
    m = UsdGeom.Mesh.Define(stage, "/World/Square")
    m.CreatePointsAttr([(-500, -500, 0), (500, -500, 0), (500, 500, 0), (-500, 500, 0)])
    m.CreateFaceVertexCountsAttr([4])
    m.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    cam = UsdGeom.Camera.Define(stage, "/World/Cam")
    cam.CreateFocalLengthAttr(35.0)
    cam.CreateHorizontalApertureAttr(36.0)
    cam.CreateVerticalApertureAttr(24.0)
    cam.AddTranslateOp().Set(Gf.Vec3d(600, -1800, 700))
    cam.AddRotateXYZOp().Set(Gf.Vec3f(70, 0, 18))
    stage.GetRootLayer().Save()
    return stage


def mesh_light():
    """meshlight.usda: a 2 x 1 quad mesh with MeshLightAPI (intensity 5, exposure 1, an orange
    colour, normalize), beside a plain quad: the first is an area light of its own shape."""
    stage = Usd.Stage.CreateNew(path("meshlight.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.Xform.Define(stage, "/World")
    for name, x in [("Panel", 0.0), ("Plain", 3.0)]:
        m = UsdGeom.Mesh.Define(stage, f"/World/{name}")
        m.CreatePointsAttr([(x, 0, 0), (x + 2, 0, 0), (x + 2, 1, 0), (x, 1, 0)])
        m.CreateFaceVertexCountsAttr([4])
        m.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
        m.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    light = UsdLux.MeshLightAPI.Apply(stage.GetPrimAtPath("/World/Panel"))
    api = UsdLux.LightAPI(light.GetPrim())
    api.CreateIntensityAttr(5.0)
    api.CreateExposureAttr(1.0)
    api.CreateColorAttr(Gf.Vec3f(1.0, 0.5, 0.25))
    api.CreateNormalizeAttr(True)
    stage.GetRootLayer().Save()
    return stage


def expected(stage, file, time=None, purpose=None):
    """What Pixar's USD computes for `stage` at time code `time` (None: the earliest): per rendered
    mesh its world points (after the up axis and units are applied by quasar: not here),
    triangles after holes, the material bound for `purpose` (None: all-purpose bindings only),
    and the camera."""
    bound = (lambda api: api.ComputeBoundMaterial()) if purpose is None else (lambda api: api.ComputeBoundMaterial(purpose))
    tc = Usd.TimeCode.EarliestTime() if time is None else Usd.TimeCode(time)
    cache = UsdGeom.XformCache(tc)
    out = {"file": file, "time_code": time, "meters_per_unit": UsdGeom.GetStageMetersPerUnit(stage),
           "up_axis": str(UsdGeom.GetStageUpAxis(stage)), "meshes": {}, "cameras": {}, "lights": {}}
    for prim in stage.Traverse():
        img = UsdGeom.Imageable(prim)
        if prim.IsA(UsdGeom.Mesh):
            if img.ComputeVisibility() == UsdGeom.Tokens.invisible or img.ComputePurpose() not in (UsdGeom.Tokens.default_, UsdGeom.Tokens.render):
                continue
            mesh = UsdGeom.Mesh(prim)
            m = cache.GetLocalToWorldTransform(prim)
            pts = [list(m.Transform(Gf.Vec3d(p))) for p in mesh.GetPointsAttr().Get(tc)]
            counts = list(mesh.GetFaceVertexCountsAttr().Get())
            holes = set(mesh.GetHoleIndicesAttr().Get() or [])
            tris = sum(c - 2 for i, c in enumerate(counts) if i not in holes)
            entry = {"world_points": pts, "triangles": tris, "material": str(bound(UsdShade.MaterialBindingAPI(prim))[0].GetPath())}
            subsets = {}
            for sub in UsdShade.MaterialBindingAPI(prim).GetMaterialBindSubsets():
                faces = list(sub.GetIndicesAttr().Get())
                subsets[str(sub.GetPath())] = {
                    "material": str(bound(UsdShade.MaterialBindingAPI(sub.GetPrim()))[0].GetPath()),
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
                "up": list(m.TransformDir(Gf.Vec3d(0, 1, 0)).GetNormalized()),
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
    result = [expected(scene(), "scene.usda"), expected(lights(), "lights.usda"), expected(composed(), "composed.usdc"),
              expected_shapes(shapes()), expected_textures(textures()), usdz(), instanced(),
              expected(arcs(), "arcs.usda", time=30.0), expected(bindings(), "bindings.usda", purpose="full"),
              expected(camera_mm(), "camera_mm.usda"), expected(mesh_light(), "meshlight.usda")]
    with open(path("expected.json"), "w") as f:
        json.dump(result, f, indent=1, sort_keys=True)
        f.write("\n")
    print("wrote", ", ".join(r["file"] for r in result), "and expected.json")
