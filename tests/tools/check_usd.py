"""Checks a .usda that `drape export` wrote with Pixar's own USD library (the
`usd-core` PyPI package): python3 check_usd.py FILE FIRST LAST VERTICES FPS [DOC_HEX].

Opens the stage, runs every validator USD registers (what `usdchecker`
runs) and checks the stage metadata, the mesh's time samples and their sizes,
and with DOC_HEX (the UTF-8 bytes of the expected layer doc string in hex, so
any text, NULs included, fits on a command line) that USD reads that doc back.
Prints a summary and exits 1 on any validation error or mismatch.
"""
import sys

from pxr import Usd, UsdGeom, UsdValidation

path, first, last, vertices, fps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
want_doc = bytes.fromhex(sys.argv[6]).decode("utf-8") if len(sys.argv) > 6 else None
stage = Usd.Stage.Open(path)
problems = []
registry = UsdValidation.ValidationRegistry()
context = UsdValidation.ValidationContext(registry.GetOrLoadAllValidators())
for error in context.Validate(stage):
    if error.GetType() == UsdValidation.ValidationErrorType.Error:
        problems.append(f"validator {error.GetName()}: {error.GetMessage()}")
    else:
        print(f"  {error.GetType()} {error.GetName()}: {error.GetMessage()}")


def expect(what, got, want):
    if got != want:
        problems.append(f"{what}: {got!r}, expected {want!r}")


expect("upAxis", UsdGeom.GetStageUpAxis(stage), UsdGeom.Tokens.y)
expect("metersPerUnit", UsdGeom.GetStageMetersPerUnit(stage), 1.0)
expect("timeCodesPerSecond", stage.GetTimeCodesPerSecond(), fps)
expect("framesPerSecond", stage.GetFramesPerSecond(), fps)
expect("startTimeCode", stage.GetStartTimeCode(), float(first))
expect("endTimeCode", stage.GetEndTimeCode(), float(last))
if want_doc is not None:
    expect("layer doc", stage.GetRootLayer().documentation, want_doc)
meshes = [UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
expect("meshes", len(meshes), 1)
if meshes:
    mesh = meshes[0]
    times = mesh.GetPointsAttr().GetTimeSamples()
    expect("point time samples", times, [float(f) for f in range(first, last + 1)])
    for t in (first, last):
        expect(f"points at {t}", len(mesh.GetPointsAttr().Get(t)), vertices)
        expect(f"normals at {t}", len(mesh.GetNormalsAttr().Get(t)), vertices)
    expect("normals interpolation", mesh.GetNormalsInterpolation(), UsdGeom.Tokens.vertex)
    st = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("st")
    expect("st interpolation", st.GetInterpolation(), UsdGeom.Tokens.vertex)
    expect("st count", len(st.Get()), vertices)
    expect("orientation", mesh.GetOrientationAttr().Get(), UsdGeom.Tokens.rightHanded)
    expect("doubleSided", mesh.GetDoubleSidedAttr().Get(), True)
for problem in problems:
    print(f"  error: {problem}")
print(f"{path}: {len(problems)} errors (USD {Usd.GetVersion()})")
sys.exit(1 if problems else 0)
