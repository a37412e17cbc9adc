"""One resolver for ``package://``, ``$(find PKG)``, ``model://`` and relative paths.

No ROS installation is needed. A package name is looked up, first match wins, in:

1. ``--package NAME=DIR`` given by the user;
2. ``--package-path DIR`` roots, scanned for ``package.xml`` (its ``<name>``) and,
   for ``model://``, ``model.config`` folders;
3. ``ROS_PACKAGE_PATH`` (scanned the same way) and ``AMENT_PREFIX_PATH``
   prefixes (``share/NAME`` when the ament index lists NAME); installed cmeel
   prefixes (``site-packages/cmeel.prefix``) count as ament prefixes, which is
   how ``package://example-robot-data/...`` resolves from PyPI;
4. for ``model://``, ``GZ_SIM_RESOURCE_PATH``, ``IGN_GAZEBO_RESOURCE_PATH`` and
   ``GAZEBO_MODEL_PATH``;
5. the input file's ancestor folders: an ancestor whose ``package.xml`` names the
   package or whose folder name is the package name, and packages found below
   each ancestor (up to three levels deep, nearest ancestor first, at most six
   ancestors up).

Every lookup records the places it tried, for the ``help`` of a diagnostic.
"""

from __future__ import annotations

import functools
import os
import re
import sys
from collections.abc import Iterable, Mapping
from dataclasses import field
from pathlib import Path

from urdftool.model import Resolution
from urdftool.records import record

_NAME = re.compile(rb"<name>\s*([^<\s]+)\s*</name>")
_SKIP_DIRS = {
    ".git", ".hg", ".svn", "node_modules", "__pycache__", ".venv", "venv", "build", "install", "log",
}
SCAN_DEPTH = 3
ANCESTOR_LEVELS = 6


def package_name(package_xml: Path) -> str | None:
    """The ``<name>`` in a ``package.xml`` (or a Gazebo ``model.config``'s folder)."""
    try:
        head = package_xml.read_bytes()[:65536]
    except OSError:
        return None
    match = _NAME.search(head)
    return match.group(1).decode("utf-8", "replace") if match else None


def _scan(root: Path, depth: int, found: dict[str, Path], marker: str = "package.xml",
          twins: dict[str, list[Path]] | None = None) -> None:
    """Record ``name -> folder`` for every ``package.xml`` at most *depth* levels below *root*,
    the first in name order; a later folder of a name already found goes to *twins*."""
    try:
        entries = sorted(os.scandir(root), key=lambda e: e.name)
    except OSError:
        return
    names = {e.name for e in entries}
    if marker in names:
        name = package_name(root / marker) if marker == "package.xml" else root.name
        if name and name not in found:
            found[name] = root
        elif name and twins is not None:
            twins.setdefault(name, []).append(root)
    if depth <= 0:
        return
    for entry in entries:
        if entry.name in _SKIP_DIRS or entry.name.startswith("."):
            continue
        try:
            is_dir = entry.is_dir(follow_symlinks=False)
        except OSError:
            continue
        if is_dir:
            _scan(Path(entry.path), depth - 1, found, marker, twins)


@functools.lru_cache(maxsize=1)
def _cmeel_prefixes() -> list[Path]:
    out = []
    for entry in sys.path:
        candidate = Path(entry) / "cmeel.prefix"
        if candidate.is_dir():
            out.append(candidate)
    return out


#: The environment variables the search reads (see the module docstring).
SEARCH_VARIABLES = ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "GZ_SIM_RESOURCE_PATH",
                    "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH")


def _search_environ() -> dict[str, str]:
    """The search variables of this process's environment (a copy of the whole environment
    decoded every variable, once per file checked)."""
    return {name: os.environ[name] for name in SEARCH_VARIABLES if name in os.environ}


def _ancestors(folder: Path) -> list[Path]:
    """*folder* and the folders above it, :data:`ANCESTOR_LEVELS` of them at most."""
    return [folder, *folder.parents][: ANCESTOR_LEVELS + 1]


def _env_paths(name: str, environ: Mapping[str, str]) -> list[Path]:
    return [Path(p) for p in environ.get(name, "").split(os.pathsep) if p]


@record(frozen=False)
class Lookup:
    """The result of resolving one URI or package name (:meth:`recorded` is what the model keeps)."""

    path: str | None
    tried: list[str] = field(default_factory=list)
    package: str | None = None
    #: the package itself was not found (as opposed to a missing file inside it)
    package_missing: bool = False
    #: for a URI inside a package or model that was found: that package's folder
    package_dir: str | None = None

    def recorded(self) -> Resolution:
        """This lookup as the model records it on a mesh (immutable)."""
        return Resolution(self.path, tuple(self.tried), self.package, self.package_missing, self.package_dir)


@record(frozen=False)
class PackageResolver:
    """Finds ROS packages and Gazebo models on disk; see the module docstring for the order."""

    packages: dict[str, Path] = field(default_factory=dict)
    package_paths: list[Path] = field(default_factory=list)
    environ: Mapping[str, str] = field(default_factory=lambda: _search_environ())
    _scanned: dict[str, dict[str, Path]] = field(default_factory=dict, repr=False)
    #: (package, folder asking) -> lookup; a robot names the same package hundreds of times
    _found: dict[tuple[str, str], Lookup] = field(default_factory=dict, repr=False)
    #: (URI, file it is written in) -> the lookup as a model records it (:meth:`resolution`)
    _resolutions: dict[tuple[str, str], Resolution] = field(default_factory=dict, repr=False)
    #: (package, file asking) -> the package's lookup as recorded (:meth:`_recorded`)
    _packages_asked: dict[tuple[str, str], Resolution] = field(default_factory=dict, repr=False)
    #: package folder taken -> the other folders of that package's name under the same root
    _twins: dict[str, list[str]] = field(default_factory=dict, repr=False)

    @classmethod
    def create(
        cls,
        packages: Mapping[str, str | os.PathLike[str]] | None = None,
        package_paths: Iterable[str | os.PathLike[str]] = (),
        environ: Mapping[str, str] | None = None,
    ) -> PackageResolver:
        return cls(
            packages={k: Path(v).resolve() for k, v in (packages or {}).items()},
            package_paths=[Path(p).resolve() for p in package_paths],
            environ=_search_environ() if environ is None else dict(environ),
        )

    def _scan_root(self, root: Path, depth: int = SCAN_DEPTH, marker: str = "package.xml") -> dict[str, Path]:
        key = f"{marker}:{depth}:{root}"
        if key not in self._scanned:
            found: dict[str, Path] = {}
            twins: dict[str, list[Path]] = {}
            _scan(root, depth, found, marker, twins)
            self._scanned[key] = found
            for name, others in twins.items():
                self._twins.setdefault(str(found[name]), []).extend(str(other) for other in others)
        return self._scanned[key]

    def twins(self, package_dir: str) -> list[str]:
        """The other folders of the package at *package_dir* found under the same search root:
        two ``package.xml`` of one name, of which the first in name order was taken. colcon
        refuses such a workspace; a search path of several roots (an overlay) is not a twin."""
        return list(self._twins.get(package_dir, ()))

    def find_package(self, name: str, near: str | os.PathLike[str] | None = None) -> Lookup:
        """The folder of package *name*; *near* is the file that asks (its ancestors are searched)."""
        key = (name, os.path.dirname(os.path.abspath(near)) if near is not None else "")
        if key not in self._found:
            self._found[key] = self._find_package(name, near)
        found = self._found[key]
        return Lookup(found.path, list(found.tried), found.package, found.package_missing)

    def _find_package(self, name: str, near: str | os.PathLike[str] | None) -> Lookup:
        tried: list[str] = []
        if name in self.packages:
            return Lookup(str(self.packages[name]), tried, name)
        tried.append("--package NAME=DIR options")
        for root in self.package_paths + _env_paths("ROS_PACKAGE_PATH", self.environ):
            found = self._scan_root(root)
            if name in found:
                return Lookup(str(found[name]), tried, name)
            tried.append(f"packages under {root}")
        prefixes = _env_paths("AMENT_PREFIX_PATH", self.environ) + _cmeel_prefixes()
        for prefix in prefixes:
            # os.path, not pathlib: every file checked looks up its packages afresh
            share = os.path.join(prefix, "share")
            marker = os.path.join(share, "ament_index", "resource_index", "packages", name)
            if os.path.exists(marker) and os.path.isdir(os.path.join(share, name)):
                return Lookup(os.path.join(share, name), tried, name)
            tried.append(f"ament prefix {prefix}")
        if near is not None:
            hit = self._find_near(name, Path(near).resolve(), tried)
            if hit is not None:
                return Lookup(str(hit), tried, name)
        return Lookup(None, tried, name, package_missing=True)

    def _find_near(self, name: str, start: Path, tried: list[str]) -> Path | None:
        ancestors = _ancestors(start if start.is_dir() else start.parent)
        for ancestor in ancestors:
            xml = ancestor / "package.xml"
            if ancestor.name == name or (xml.exists() and package_name(xml) == name):
                return ancestor
        for ancestor in ancestors:
            found = self._scan_root(ancestor)
            if name in found:
                return found[name]
            tried.append(f"packages under {ancestor}")
        return None

    def find_model(self, name: str, near: str | os.PathLike[str] | None = None) -> Lookup:
        """The folder of Gazebo model *name* (a folder holding ``model.config``)."""
        tried: list[str] = []
        if name in self.packages:
            return Lookup(str(self.packages[name]), tried, name)
        roots = self._gazebo_paths()
        if near is not None:
            folder = Path(near).resolve()
            roots += _ancestors(folder if folder.is_dir() else folder.parent)
        for root in roots:
            candidate = root / name
            if (candidate / "model.config").exists() or (candidate / "model.sdf").exists():
                return Lookup(str(candidate), tried, name)
            found = self._scan_root(root, 2, "model.config")
            if name in found:
                return Lookup(str(found[name]), tried, name)
            tried.append(f"models under {root}")
        package = self.find_package(name, near)
        if package.path:
            return package
        return Lookup(None, tried, name, package_missing=True)

    def resolve_uri(self, uri: str, base: str | os.PathLike[str]) -> Lookup:
        """Resolve a mesh or include URI written in the file *base*.

        Accepts ``package://PKG/rel``, ``model://MODEL/rel``, ``file:///abs``,
        absolute paths and paths relative to *base*'s folder. The returned path
        may not exist; ``tried`` lists where it looked.
        """
        for scheme, finder in (("package://", self.find_package), ("model://", self.find_model)):
            if uri.startswith(scheme):
                rest = uri[len(scheme) :].lstrip("/")
                pkg, _, rel = rest.partition("/")
                found = finder(pkg, base)
                if found.path is None:
                    return found
                # 'model://ocean//media/x': the simulators join the two parts as text, and a
                # doubled slash is still one folder; os.path.join would start again at the root
                target = os.path.join(found.path, rel.lstrip("/"))
                found.tried.append(target)
                return Lookup(target, found.tried, pkg, package_dir=found.path)
        if uri.startswith("file://"):
            path = uri[len("file://") :]
            return Lookup(path, [path]) if os.path.isabs(path) else self._relative_file(path, base)
        # os.path, not pathlib.resolve(): no symlink walk or object churn per mesh
        # (a robot names thousands of them)
        target = uri if os.path.isabs(uri) else os.path.join(os.path.dirname(os.path.abspath(base)), uri)
        return Lookup(target, [target])

    def _gazebo_paths(self, *more: str) -> list[Path]:
        """``--package-path`` and the folders Gazebo looks in for a ``model://`` (gz-sim's
        ``GZ_SIM_RESOURCE_PATH`` and ``IGN_GAZEBO_RESOURCE_PATH``, Classic's ``GAZEBO_MODEL_PATH``),
        then those of the variables *more*."""
        names = ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", *more, "GAZEBO_MODEL_PATH")
        return self.package_paths + [path for name in names for path in _env_paths(name, self.environ)]

    def _relative_file(self, path: str, base: str | os.PathLike[str]) -> Lookup:
        """A relative ``file://`` path, found as gz-common's ``FindFileURI`` and Gazebo Classic's
        ``FindFile`` find it: in the resource paths (``GZ_SIM_RESOURCE_PATH``,
        ``IGN_GAZEBO_RESOURCE_PATH``, ``GAZEBO_RESOURCE_PATH``, ``GAZEBO_MODEL_PATH``, and
        ``--package-path``), and in the describing file's folder and the folders above it, where a
        project's models folder usually sits; the working directory last, as the simulators try it
        too. Where it is found nowhere, the first place tried is returned."""
        roots = (
            self._gazebo_paths("GAZEBO_RESOURCE_PATH")
            + _ancestors(Path(os.path.abspath(base)).parent)
            + [Path.cwd()]
        )
        tried = [os.path.join(root, path) for root in roots]
        found = next((target for target in tried if os.path.isfile(target)), None)
        return Lookup(found or tried[0], tried)

    def resolution(self, uri: str, base: str) -> Resolution:
        """:meth:`resolve_uri` as the model records it on a mesh, once per URI and file: a robot
        names each mesh file from several links, and nothing a lookup reads changes within a run."""
        key = (uri, base)
        found = self._resolutions.get(key)
        if found is None:
            found = self._resolutions[key] = self._recorded(uri, base)
        return found

    def _recorded(self, uri: str, base: str) -> Resolution:
        """``resolve_uri(uri, base).recorded()``; a ``package://`` URI looks its package up once per
        package and file (a robot's meshes all name the same one or two packages)."""
        if not uri.startswith("package://"):
            return self.resolve_uri(uri, base).recorded()
        name, _, rel = uri[len("package://"):].lstrip("/").partition("/")
        package = self._packages_asked.get((name, base))
        if package is None:
            package = self._packages_asked[(name, base)] = self.find_package(name, base).recorded()
        if package.path is None:
            return package
        target = os.path.join(package.path, rel.lstrip("/"))
        return Resolution(target, (*package.tried, target), name, False, package.path)
