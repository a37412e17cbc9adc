"""scripts/review_realworld.py sorts a model's errors against its manifest entry.

Only the sorting is tested, on made-up findings: the corpus itself is not in the
repository, and the script that checks it is run by hand (docs/realworld.md).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from tests.conftest import ROOT

sys.path.insert(0, str(ROOT / "scripts"))
import review_realworld

CORPUS = Path("/corpus")
ENTRY = {
    "path": "arm/urdf/arm.xacro",
    "xacro_args": {"gazebo": "true"},
    "package_paths": ["arm"],
    "omitted_meshes": ["arm/meshes/base.dae", "arm/meshes/finger.gltf"],
    "expected": [{"code": "I005", "element": "link[cam]/inertial/inertia", "reason": "A+B<C"},
                 {"code": "G001", "element": "gazebo[stick]", "reason": "dead block"}],
    "known_false": [{"code": "S017", "element": "link[free]"}],
}


def finding(code: str, element: str, severity: str = "error", **data: str) -> dict[str, object]:
    names = {"M002": "mesh-not-found", "M003": "mesh-unreadable"}
    return {"code": code, "name": names.get(code, code), "severity": severity, "element": element,
            "message": f"{code} on {element}", "data": data}


def test_each_error_is_expected_omitted_known_false_or_unexpected() -> None:
    found = [
        finding("I005", "link[cam]/inertial/inertia"),
        finding("M002", "link[base]/visual/geometry/mesh", path="/corpus/arm/meshes/base.dae"),
        finding("M002", "link[hand]/visual/geometry/mesh", path="/corpus/arm/meshes/hand.dae"),
        finding("M003", "link[finger]/visual/geometry/mesh", path="/corpus/arm/meshes/finger.gltf"),
        finding("M003", "link[palm]/visual/geometry/mesh", path="/corpus/arm/meshes/palm.gltf"),
        finding("S017", "link[free]"),
        finding("J001", "joint[j1]"),
        finding("G001", "gazebo[stick]", severity="warning"),
        finding("I006", "link[cam]/inertial", severity="warning"),
    ]
    review = review_realworld.review(ENTRY, found, CORPUS)
    assert review.errors == 7
    assert [d["code"] for d in review.expected] == ["I005"]
    # a glTF vendored without its .bin buffer is unreadable, not missing: omitted all the same
    assert [d["element"] for d in review.omitted] == ["link[base]/visual/geometry/mesh",
                                                      "link[finger]/visual/geometry/mesh"]
    assert [d["code"] for d in review.known_false] == ["S017"]
    assert [d["code"] for d in review.unexpected] == ["M002", "M003", "J001"]
    assert review.vanished == [("G001", "gazebo[stick]", "now warning")]


def test_the_check_runs_as_a_user_runs_it() -> None:
    argv = review_realworld.command(ENTRY, CORPUS, dynamics=False)
    assert argv[1:5] == ["-m", "urdftool", "check", "/corpus/arm/urdf/arm.xacro"]
    assert {"--format", "json", "--isolated", "--no-dynamics", "gazebo:=true", "/corpus/arm"} <= set(argv)
    assert review_realworld.label(ENTRY) == "arm/urdf/arm.xacro [gazebo:=true]"


def test_an_srdf_and_controllers_the_discovery_cannot_pair_are_passed() -> None:
    entry = {**ENTRY, "srdf": "arm_moveit_config/config/arm.srdf", "controllers": "arm/config/c.yaml"}
    argv = review_realworld.command(entry, CORPUS, dynamics=True)
    assert argv[argv.index("--srdf") + 1] == "/corpus/arm_moveit_config/config/arm.srdf"
    assert argv[argv.index("--controllers") + 1] == "/corpus/arm/config/c.yaml"
    assert "--srdf" not in review_realworld.command(ENTRY, CORPUS, dynamics=True)



def test_an_environment_the_upstream_setup_script_exports_is_set_and_labelled(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # kinova-movo's xacro reads $(optenv MOVO_HAS_BODY false): the model depends on the shell
    monkeypatch.delenv("MOVO_HAS_BODY", raising=False)
    entry = {"path": "movo/urdf/movo.urdf.xacro", "env": {"MOVO_HAS_BODY": "true"}}
    assert review_realworld.environment(entry)["MOVO_HAS_BODY"] == "true"
    assert "MOVO_HAS_BODY" not in review_realworld.environment(ENTRY)
    assert review_realworld.label(entry) == "movo/urdf/movo.urdf.xacro (env MOVO_HAS_BODY=true)"
    assert review_realworld.label({**entry, "xacro_args": {"arm": "left"}}) == \
        "movo/urdf/movo.urdf.xacro [arm:=left] (env MOVO_HAS_BODY=true)"


def test_saved_report_names_stay_within_file_name_limits() -> None:
    assert review_realworld.report_name(ENTRY) == "arm__urdf__arm.xacro_[gazebo:=true].json"
    many = {**ENTRY, "xacro_args": {f"argument_{i}": "rotors_gazebo/resource/fixed_wing.yaml"
                                    for i in range(12)}}
    name = review_realworld.report_name(many)
    assert len(name.encode("utf-8")) <= 255
    assert name != review_realworld.report_name({**many, "xacro_args": {"other": "1"}})
