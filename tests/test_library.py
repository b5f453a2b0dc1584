"""Library builds (``rswarp build``): one packaged asset per Library and Variant, metadata,
previews rendered with Warp, and a failing library among good ones."""

from __future__ import annotations

import dataclasses
import zipfile

import numpy as np
import pytest

import rswarp
from rswarp import examples
from rswarp.cli import main
from rswarp.geometry import meshes
from rswarp.report.library import build_library
from rswarp.sim.preview import View, camera, home_scene, render

from conftest import DATA

CELL = DATA / "library" / "cell" / "Cell.xml"
ARM = DATA / "library" / "cell" / "parts" / "IRB9_1_1__01.rsxml"
SIZE = 128  # preview size in these tests: small and quick


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("lib")
    return build_library(CELL, out, size=SIZE), out


def layer_data(path):
    from pxr import Usd

    stage = Usd.Stage.Open(str(path))
    return stage.GetRootLayer().customLayerData["rswarp:library"], stage.GetDefaultPrim().GetAssetInfo()


def test_one_asset_per_library_and_variant_and_a_failure_reported(built):
    build, out = built
    assert [(r.library, r.status) for r in build.results] == [
        ("IRB9_1_1__01.rslib", "built"), ("IRB9_1_1__01.rslib:Near", "built"),
        ("IRB9_1_1_FLIPPED__01.rslib", "built"), ("IRB9_missing.rslib", "failed")]
    assert sorted(p.name for p in out.iterdir()) == [  # nothing of the failure; the manifest of what was written
        ".rswarp.json", "IRB9_1_1_FLIPPED__01.png", "IRB9_1_1_FLIPPED__01.usdz", "IRB9_1_1_NEAR__01.png", "IRB9_1_1_NEAR__01.usdz",
        "IRB9_1_1__01.png", "IRB9_1_1__01.usdz"]
    assert zipfile.ZipFile(out / "IRB9_1_1__01.usdz").read("IRB9_1_1__01.thumbnail.png") == \
        (out / "IRB9_1_1__01.png").read_bytes()
    failed = build.results[-1]
    assert failed.message.startswith(f"{CELL}:31: ") and "IRB9_missing.rsxml' not found" in failed.message
    assert not build.ok


def test_properties_inherit_and_override(built):
    _, out = built
    data, info = layer_data(out / "IRB9_1_1__01.usdz")
    assert (data["title"], data["author"], data["revision"]) == ("IRB 9 test arm", "rswarp tests", "01")
    assert data["properties"] == {"Category": "Test robots"}
    assert data["source"] == "parts\\IRB9_1_1__01.rsxml" and data["fileName"] == "IRB9_1_1__01.rslib"
    assert data["descriptions"] == {"de": "Ein zweiachsiger Testarm.", "en": "A two-axis test arm."}
    assert info["name"] == "IRB 9 test arm" and info["version"] == "01"
    near, _ = layer_data(out / "IRB9_1_1_NEAR__01.usdz")
    assert near["title"] == "IRB 9 test arm, near" and near["author"] == "rswarp tests"
    assert near["variant"]["name"] == "Near"
    flipped, info = layer_data(out / "IRB9_1_1_FLIPPED__01.usdz")
    assert flipped["revision"] == "03" and info["version"] == "03"


def test_revision_that_disagrees_with_the_name_is_a_warning(built):
    build, _ = built
    flipped = build.results[2]
    assert any("Cell.xml:24: warning: Revision 03 disagrees with the revision 01" in w for w in flipped.warnings)
    assert not any("Revision" in w for w in build.results[0].warnings)


def test_usdz_opens_holds_its_thumbnail_and_passes_the_validator(built):
    from pxr import Usd, UsdMedia

    _, out = built
    path = out / "IRB9_1_1__01.usdz"
    assert sorted(zipfile.ZipFile(path).namelist()) == ["IRB9_1_1__01.thumbnail.png", "IRB9_1_1__01.usdc"]
    stage = Usd.Stage.Open(str(path))
    thumb = UsdMedia.AssetPreviewsAPI(stage.GetDefaultPrim()).GetDefaultThumbnails().defaultImage
    assert thumb.resolvedPath.endswith("[IRB9_1_1__01.thumbnail.png]")
    collisions = [p for p in stage.Traverse() if p.GetName() == "collisions"]
    assert collisions and all(p.GetChildren() for p in collisions)  # convex pieces stored, not recomputed
    validator = pytest.importorskip("omni.asset_validator")
    results = validator.ValidationEngine().validate(str(path))
    errors = [i for i in results.issues() if i.severity in (validator.IssueSeverity.ERROR, validator.IssueSeverity.FAILURE)]
    assert errors == [], "\n".join(f"{i.rule}: {i.message}" for i in errors)


def test_builds_are_deterministic(built, tmp_path):
    _, out = built
    again = build_library(CELL, tmp_path, size=SIZE)
    for r in again.results[:3]:
        name = r.output.split("/")[-1]
        assert (tmp_path / name).read_bytes() == (out / name).read_bytes()


def test_a_mesh_shared_by_libraries_is_read_once_per_build(monkeypatch, tmp_path):
    calls = []
    parse = meshes._parse
    monkeypatch.setattr(meshes, "_parse", lambda path, suffix: calls.append(path) or parse(path, suffix))
    monkeypatch.setattr(meshes, "_MESHES", type(meshes._MESHES)())
    build_library(CELL, tmp_path, size=16)
    assert sorted(p.split("/")[-1] for p in calls) == ["arm.stl", "post.stl", "slab.stl"]


def test_image_source_is_the_given_picture(tmp_path):
    from PIL import Image

    Image.new("RGB", (40, 30), (200, 10, 10)).save(tmp_path / "pic.bmp")
    lib = tmp_path / "Pic.xml"
    lib.write_text(f'''<LibraryCompiler xmlns="urn:abb-robotics-robotstudio-librarycompiler">
      <Library source="{ARM}"><DocumentProperties><Title>Given</Title><Image source="pic.bmp"/></DocumentProperties>
      </Library></LibraryCompiler>''')
    (r,) = build_library(lib, tmp_path / "out").results
    with Image.open(tmp_path / "out" / "IRB9_1_1__01.png") as im:
        assert r.status == "built" and im.size == (40, 30) and im.getpixel((5, 5)) == (200, 10, 10, 255)


def test_component_layout_is_a_folder_per_asset(tmp_path):
    build = build_library(CELL, tmp_path, layout="component", size=16)
    folder = tmp_path / "IRB9_1_1__01"
    assert sorted(p.name for p in folder.iterdir()) == [
        ".rswarp.json", "IRB9_1_1__01.thumbnail.png", "IRB9_1_1__01.usda", "IRB9_1_1__01_Payload"]
    assert build.results[0].output == str(folder)


def test_all_failing_leaves_no_folder(tmp_path):
    bad = tmp_path / "Bad.xml"
    bad.write_text('<LibraryCompiler xmlns="urn:abb-robotics-robotstudio-librarycompiler">'
                   '<Library source="nothing.rsxml"/></LibraryCompiler>')
    build = build_library(bad, tmp_path / "out", size=16)
    assert [r.status for r in build.results] == ["failed"] and not (tmp_path / "out").exists()


def test_cli_table_and_exit_code(tmp_path, capsys):
    assert main(["build", str(CELL), "-o", str(tmp_path), "--size", "16"]) == 1
    out = capsys.readouterr().out
    assert "IRB9_1_1_NEAR__01.usdz" in out and "failed" in out and "3 of 4 built" in out
    ok = tmp_path / "Ok.xml"
    ok.write_text(CELL.read_text().split("  <Library source=\"parts\\IRB9_missing")[0] + "</LibraryCompiler>\n")
    (tmp_path / "parts").symlink_to(CELL.parent / "parts")
    assert main(["build", str(ok), "-o", str(tmp_path / "ok"), "--size", "16"]) == 0


def test_irb1300_names_the_missing_geometry(tmp_path):
    build = build_library(examples.IRB1300_LIBRARY, tmp_path, size=16)
    (r,) = build.results
    assert r.status == "built"
    assert any("no preview: no part has a mesh ('Base' (link0.SAT), 'Link1' (link1_900.SAT)" in w for w in r.warnings)


# -- the preview image --------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def arm_scene():
    mech = rswarp.load(ARM)
    return home_scene(mech, rswarp.Kinematics(mech).fk64(mech.home_position()[None])[0])


def projection(scene, view: View, size: int) -> np.ndarray:
    """The scene's triangles projected by the preview's camera and filled by PIL: the silhouette."""
    from PIL import Image, ImageDraw

    c = camera(scene.vertices, view, size)
    rel = scene.vertices - c["origin"]
    x = rel @ c["right"] / c["pixel"] + size / 2
    y = size / 2 - rel @ c["up"] / c["pixel"]
    img = Image.new("L", (size, size), 0)
    draw = ImageDraw.Draw(img)
    for f in scene.faces:
        draw.polygon([(x[i], y[i]) for i in f], fill=255)
    return np.asarray(img) > 127


def silhouette(scene, view: View, size: int = SIZE) -> np.ndarray:
    return render(scene, view, size)[..., 3] >= 128


def iou(a: np.ndarray, b: np.ndarray) -> float:
    return (a & b).sum() / (a | b).sum()


@pytest.mark.parametrize("view", [View(), View(zoom=50, panx=10, pany=-20), View(flip=True)])
def test_render_silhouette_matches_the_projected_meshes(arm_scene, view):
    assert iou(silhouette(arm_scene, view), projection(arm_scene, view, SIZE)) > 0.95


def test_pan_moves_and_zoom_scales_the_component_as_documented(arm_scene):
    base = silhouette(arm_scene, View())
    small = silhouette(arm_scene, View(zoom=-50))  # half as large: a quarter of the area
    assert small.sum() / base.sum() == pytest.approx(0.25, rel=0.1)
    ys, xs = np.nonzero(small)
    my, mx = np.nonzero(silhouette(arm_scene, View(zoom=-50, panx=10, pany=20)))  # still wholly in the image
    assert mx.mean() - xs.mean() == pytest.approx(0.10 * SIZE, abs=0.5)  # right by 10 % of the width
    assert ys.mean() - my.mean() == pytest.approx(0.20 * SIZE, abs=0.5)  # up by 20 % of the height


def test_flip_views_the_other_side(arm_scene):
    mirrored = dataclasses.replace(arm_scene, vertices=arm_scene.vertices * [1, -1, 1],
                                   faces=arm_scene.faces[:, ::-1])
    assert iou(silhouette(mirrored, View(flip=True)), silhouette(arm_scene, View())[:, ::-1]) > 0.97
    assert iou(silhouette(arm_scene, View(flip=True)), silhouette(arm_scene, View())) < 0.9


def test_bad_flip_is_refused():
    from rswarp.rsxml.library import Image

    with pytest.raises(ValueError, match="flip='sideways'"):
        View.of(Image(generate=True, flip="sideways"))
