"""Files from the page, in a real browser (Debian's chromium through Playwright) against a
real server: the export dialog (a project's take exported as .glb and .usd as browser
downloads: the Khronos validator finds no error, three.js and pxr play the take within
its tolerance), closed by Escape with the focus back, a refusal shown in it; the project
dialog (a take made in the page, saved as a copy the studio goes on with, the first opened
again). Every test checks the page drew something."""

from __future__ import annotations

import json
import urllib.request
from pathlib import Path

import numpy as np

import pytest

from clips import validate
from sketchanim.anim.attributes import POSITION
from sketchanim.anim.layers import reduce_samples
from sketchanim.anim.tracks import ContinuousTrack, Take
from sketchanim.project.store import Project
from sketchanim.studio.defaults import default_scene
from studio_browser import curve, drag, drew_something, last_take, project, studio_server
from threejs_client import three_play

PATH = "box.position"
#: Where the dialog's screenshot goes (for a look with an image viewer).
SHOTS = Path(__file__).resolve().parents[2] / "out" / "screenshots"


def _make_take(page) -> None:  # noqa: ANN001
    """Record mode on, one drag of the box, record mode off."""
    page.click("[data-testid=record]")
    page.wait_for_timeout(100)
    start = page.evaluate("viewport.screenOf('box')")
    s = np.linspace(0, 1, 45)
    drag(page, start, list(zip(160 * s, -60 * np.sin(np.pi * s))))
    assert not last_take(page)["errors"]
    page.click("[data-testid=record]")


#: The take of the box's position the export tests' project holds.
T = np.linspace(0, 2, 121)
POS = np.c_[np.sin(2 * T), 0.5 + 0.2 * T, np.cos(3 * T)]
TOL = 0.005


@pytest.fixture
def take_studio(tmp_path: Path):  # noqa: ANN201
    """A studio on ``studio.sketchanim``: the default scene, the box's position recorded
    in one take (as the recorder keeps it: its samples reduced within the tolerance)."""
    track = ContinuousTrack(PATH, POSITION, reduce_samples(POSITION, T, POS, TOL, 4), TOL, (Take(T, POS),))
    Project(tmp_path / "studio.sketchanim").save(default_scene(), {PATH: track})
    with studio_server(tmp_path / "studio.sketchanim") as url:
        yield url


def _shoot_at(page, name: str, back: tuple[float, float], file: str) -> None:  # noqa: ANN001
    """A look at object ``name`` (the camera ``back`` = (across, up) metres off it, looking at
    it), the notices dismissed, kept in ``SHOTS / file``."""
    page.evaluate(f"""(() => {{ const p = viewport.nodes.get('{name}').root.position;
        viewport.orbit.target.copy(p); viewport.camera.position.set(p.x + {back[0]}, p.y + {back[1]}, p.z + {back[0]});
        viewport.camera.lookAt(p); viewport.orbit.update(); }})()""")
    page.wait_for_timeout(300)
    SHOTS.mkdir(parents=True, exist_ok=True)
    while page.locator("[data-testid=notice-dismiss]").count():       # the refusals' notices off the view
        page.locator("[data-testid=notice-dismiss]").first.click()
    page.locator("[data-testid=viewport]").screenshot(path=str(SHOTS / file))


def _download(page, testid: str, folder: Path) -> Path:  # noqa: ANN001
    """Open the dialog, choose ``testid``, the browser's download saved in ``folder``."""
    page.click("[data-testid=export]")
    page.wait_for_selector(f"[data-testid={testid}]")
    with page.expect_download() as info:
        page.click(f"[data-testid={testid}]")
    download = info.value
    path = folder / download.suggested_filename
    download.save_as(path)
    page.wait_for_selector("[data-testid=export-dialog]", state="hidden")
    return path


def test_export_dialog_downloads_a_glb_three_js_plays_within_tolerance(_page, take_studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    page = _page(take_studio)
    page.click("[data-testid=export]")
    dialog = page.locator("[data-testid=export-dialog]")
    dialog.locator("[data-testid=export-glb]").wait_for()
    text = dialog.inner_text()
    assert "three.js" in text and "within 5 mm" in text and "Blender's own glTF importer" in text
    SHOTS.mkdir(parents=True, exist_ok=True)
    dialog.screenshot(path=str(SHOTS / "export-dialog.png"))
    recording = "document.querySelector('[data-testid=record]').classList.contains('on')"
    page.keyboard.press("r")                        # the record shortcut: not under the dialog
    assert page.evaluate(recording) is False, "a key in the dialog reached the shortcuts"
    page.keyboard.press("Escape")
    page.wait_for_selector("[data-testid=export-dialog]", state="hidden")
    assert page.evaluate("document.activeElement.dataset.testid") == "export", "the focus did not come back"
    page.keyboard.press("r")                        # the shortcuts are back
    assert page.evaluate(recording) is True
    page.keyboard.press("r")

    glb = _download(page, "export-glb", tmp_path)
    assert glb.name == "studio.glb"
    assert page.evaluate("document.activeElement.dataset.testid") == "export"
    (report,) = validate(glb)
    assert report["numErrors"] == 0, report["messages"][:3]
    played = three_play(glb, T)["box"]["position"]
    assert np.abs(played - POS).max() <= TOL, "three.js plays the take outside its tolerance"
    assert drew_something(page) > 5 and not page.errors


def test_export_dialog_downloads_usd_pxr_opens_and_shows_a_refusal(_page, take_studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    from pxr import Usd

    page = _page(take_studio)
    usd = _download(page, "export-usd", tmp_path)
    assert usd.name == "studio.usd"
    stage = Usd.Stage.Open(str(usd))
    rate = stage.GetTimeCodesPerSecond()
    translate = stage.GetPrimAtPath("/box").GetAttribute("xformOp:translate")
    played = np.array([translate.Get(float(t * rate)) for t in T])
    assert np.abs(played - POS).max() <= TOL
    # a refusal (as a server without usd-core answers) is shown in the dialog, which stays open
    detail = "USD export needs usd-core: pip install 'sketchanim[usd]'"
    page.route("**/api/export?format=usd", lambda route: route.fulfill(
        status=400, content_type="application/json", body=json.dumps({"detail": detail})))
    page.click("[data-testid=export]")
    page.click("[data-testid=export-usd]")
    error = page.locator("[data-testid=export-dialog-error]")
    error.wait_for()
    assert detail in error.inner_text() and "studio.usd" in error.inner_text()
    assert page.locator("[data-testid=export-dialog]").is_visible()
    page.click("[data-testid=export-dialog-close]")
    page.wait_for_selector("[data-testid=export-dialog]", state="hidden")
    assert drew_something(page) > 5 and not page.errors


def test_save_as_goes_on_with_the_copy_and_open_goes_back(_page, studio: str, tmp_path: Path) -> None:  # noqa: ANN001
    page = _page(studio)
    _make_take(page)
    page.click("[data-testid=files]")
    field = page.locator("[data-testid=save-as-name]")
    assert field.input_value() == "studio-copy.sketchanim"
    # a bad name: refused, shown, the dialog stays open, nothing written
    field.fill("")
    page.keyboard.type("../up.sketchanim")              # typed: the keys reach the field, not the shortcuts
    assert field.input_value() == "../up.sketchanim"
    page.keyboard.press("Enter")
    error = page.locator("[data-testid=files-dialog-error]")
    error.wait_for()
    assert "not a path" in error.inner_text() and not (tmp_path.parent / "up.sketchanim").exists()
    field.fill("take2.sketchanim")
    page.keyboard.press("Enter")
    page.wait_for_selector("[data-testid=files-dialog]", state="hidden")
    page.wait_for_function("document.getElementById('project').textContent === 'take2.sketchanim'")
    assert (tmp_path / "take2.sketchanim").is_file()
    doc = project(studio)
    assert curve(doc, PATH) is not None, "the copy lost the take"
    with urllib.request.urlopen(studio + "api/state") as r:
        assert json.load(r)["project"] == "take2.sketchanim"
    # open the first again, from the files folder's list
    page.click("[data-testid=files]")
    page.wait_for_selector("[data-testid=open-file]")
    recent = page.locator("[data-testid=files-dialog]").inner_text()
    assert "take2.sketchanim" in recent and "open now" in recent
    page.click(f"[data-testid=open-file][data-path='{tmp_path / 'studio.sketchanim'}']")
    page.wait_for_selector("[data-testid=files-dialog]", state="hidden")
    page.wait_for_function("document.getElementById('project').textContent === 'studio.sketchanim'")
    assert page.evaluate("document.activeElement.dataset.testid") == "files"
    assert curve(project(studio), PATH) is not None
    assert drew_something(page) > 5 and not page.errors


def test_import_a_bvh_from_the_outliner_plays_and_a_truncated_one_is_refused(_page, studio: str, data_dir: Path,
                                                                             tmp_path: Path) -> None:  # noqa: ANN001
    page = _page(studio)
    source = data_dir / "bvh" / "bandai1_walk_happy_001.bvh"
    page.set_input_files("[data-testid=import-clip]", str(source))
    status = page.locator("[data-testid=import-clip-status]")
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes('joints')",
                           timeout=120_000)
    assert "213 frames" in status.inner_text()
    doc = project(studio)
    assert curve(doc, "bandai1_walk_happy_001_Hips.position") is not None and curve(doc, "bandai1_walk_happy_001_Hips.orientation") is not None
    names = page.evaluate("studio.objects.map((o) => o.name)")
    assert "bandai1_walk_happy_001_Hips" in names and "bandai1_walk_happy_001_Head" in names
    page.wait_for_selector("[data-testid=outliner] >> text=bandai1_walk_happy_001_Hips")
    # it plays with the rest: the hips move as the transport runs
    start = page.evaluate("Array.from(studio.values.get('bandai1_walk_happy_001_Hips.position'))")
    page.click("[data-testid=play]")
    page.wait_for_timeout(1500)
    page.click("[data-testid=play]")
    moved = page.evaluate("Array.from(studio.values.get('bandai1_walk_happy_001_Hips.position'))")
    assert np.linalg.norm(np.subtract(moved, start)) > 0.05, (start, moved)
    # a truncated file: refused on the page (status and notice), the project unchanged
    before = project(studio)
    cut = tmp_path / "cut.bvh"
    data = source.read_bytes()
    cut.write_bytes(data[: len(data) // 2])
    page.set_input_files("[data-testid=import-clip]", str(cut))
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes('not imported')")
    assert "cut.bvh" in status.inner_text() and "line" in status.inner_text()
    assert "cut.bvh was not imported" in page.locator("[data-testid=notices]").inner_text()
    assert project(studio) == before
    # a 200 MB file (sparse: no disk spent): refused on the page, the project unchanged
    big = tmp_path / "big.bvh"
    with big.open("wb") as f:
        f.truncate(200 * 2**20)
    page.set_input_files("[data-testid=import-clip]", str(big))
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes('big.bvh')",
                           timeout=60_000)
    page.wait_for_function("!document.querySelector('[data-testid=import-clip]').disabled", timeout=60_000)
    assert "big.bvh was not imported" in status.inner_text() and "at most 64 MB" in status.inner_text()
    assert project(studio) == before
    assert drew_something(page) > 5 and not page.errors


def test_an_imported_skeleton_is_drawn_as_bones_that_follow_playback_and_a_grab(_page, studio: str,
                                                                               data_dir: Path) -> None:  # noqa: ANN001
    from sketchanim.formats.bvh import read_bvh

    page = _page(studio)
    source = data_dir / "bvh" / "bandai1_walk_happy_001.bvh"
    page.set_input_files("[data-testid=import-clip]", str(source))
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes('joints')",
                           timeout=120_000)
    page.wait_for_function("viewport.bones.pairs.length > 0")
    skeleton = read_bvh(source).skeleton
    prefix = "bandai1_walk_happy_001_"
    expected = {(prefix + n, prefix + skeleton.names[up]) for n, up in zip(skeleton.names, skeleton.parents) if up >= 0}

    def ends_at_joints() -> list[dict]:
        bones = page.evaluate("viewport.bones.report()")
        values = page.evaluate("Object.fromEntries([...studio.values].filter(([k]) => k.endsWith('.position'))"
                               ".map(([k, v]) => [k, Array.from(v)]))")
        for b in bones:
            assert np.allclose(b["from"], values[f"{b['child']}.position"], atol=1e-5), b
            assert np.allclose(b["to"], values[f"{b['parent']}.position"], atol=1e-5), b
        return bones

    page.wait_for_timeout(200)
    bones = ends_at_joints()
    assert {(b["child"], b["parent"]) for b in bones} == expected and len(bones) == len(expected)
    # they follow playback
    page.click("[data-testid=play]")
    page.wait_for_timeout(1200)
    page.click("[data-testid=play]")
    page.wait_for_timeout(200)
    moved = ends_at_joints()
    assert max(np.linalg.norm(np.subtract(a["from"], b["from"])) for a, b in zip(bones, moved)) > 0.05
    # a look: the camera at the hips (for the screenshot, kept in SHOTS)
    _shoot_at(page, f"{prefix}Hips", (2.2, 0.6), "bones.png")
    # and a joint moved by hand (as a grab moves it: the local value, drawn before the server hears)
    head = prefix + "Head"
    page.evaluate(f"studio.setLocal('{head}.position', [0.5, 2.5, 0.5])")
    page.wait_for_timeout(200)
    assert [b["from"] for b in ends_at_joints() if b["child"] == head] == [[0.5, 2.5, 0.5]]
    assert drew_something(page) > 5 and not page.errors


def test_import_c3d_markers_from_the_outliner_and_a_truncated_one_is_refused(_page, studio: str, data_dir: Path,
                                                                            tmp_path: Path) -> None:  # noqa: ANN001
    page = _page(studio)
    source = data_dir / "c3d" / "pyomeca_markers_analogs.c3d"
    status = page.locator("[data-testid=import-clip-status]")
    # a truncated file first: refused on the page (status and notice), the project unchanged
    before = project(studio)
    cut = tmp_path / "cut.c3d"
    data = source.read_bytes()
    cut.write_bytes(data[: len(data) // 2])
    page.set_input_files("[data-testid=import-clip]", str(cut))
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes('not imported')",
                           timeout=60_000)
    assert "cut.c3d" in status.inner_text() and "truncated" in status.inner_text()
    assert "cut.c3d was not imported" in page.locator("[data-testid=notices]").inner_text()
    assert project(studio) == before
    # the whole file: one object per marker, shown where it was seen
    page.set_input_files("[data-testid=import-clip]", str(source))
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes(' markers, ')",
                           timeout=120_000)
    assert "51 markers, 580 frames" in status.inner_text()
    names = page.evaluate("studio.objects.map((o) => o.name)")
    markers = [n for n in names if n.startswith("pyomeca_markers_analogs_")]
    assert len(markers) == 51
    assert curve(project(studio), markers[0] + ".position") is not None
    page.wait_for_selector(f"[data-testid=outliner] >> text={markers[0]}")
    _shoot_at(page, markers[0], (2.5, 1.0), "c3d-markers.png")
    assert drew_something(page) > 5 and not page.errors


def test_import_an_asf_with_its_amc_from_the_outliner_and_a_lone_or_truncated_amc_is_refused(
        _page, studio: str, data_dir: Path, tmp_path: Path) -> None:  # noqa: ANN001
    from sketchanim.formats.clip_files import read_clip

    page = _page(studio)
    asf, amc = data_dir / "amc" / "cmu_11.asf", data_dir / "amc" / "cmu_11_01.amc"
    status = page.locator("[data-testid=import-clip-status]")
    before = project(studio)
    # an .amc alone: refused on the page, nothing sent
    page.set_input_files("[data-testid=import-clip]", str(amc))
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes('not imported')")
    assert "an .asf with its .amc" in status.inner_text()
    # a truncated .amc with its .asf: refused by the server, naming the .amc
    cut = tmp_path / "cut.amc"
    text = amc.read_text()
    cut.write_text(text[: len(text) // 2].rsplit("\n", 3)[0])
    page.set_input_files("[data-testid=import-clip]", [str(asf), str(cut)])
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.startsWith('cut.amc was not')",
                           timeout=60_000)
    assert "cut.amc, line" in status.inner_text() and "truncated" in status.inner_text()
    assert project(studio) == before
    # both: the joints, parented, drawn as bones
    page.set_input_files("[data-testid=import-clip]", [str(asf), str(amc)])
    page.wait_for_function("document.querySelector('[data-testid=import-clip-status]').textContent.includes(' joints, ')",
                           timeout=120_000)
    skeleton = read_clip(amc, skeleton=asf).skeleton
    assert f"{len(skeleton.names)} joints" in status.inner_text()
    page.wait_for_function("viewport.bones.pairs.length > 0")
    assert len(page.evaluate("viewport.bones.report()")) == sum(up >= 0 for up in skeleton.parents)
    _shoot_at(page, f"cmu_11_01_{skeleton.names[0]}", (2.2, 0.6), "amc-bones.png")
    assert drew_something(page) > 5 and not page.errors
