# SPDX-License-Identifier: GPL-3.0-or-later
"""The PEP 517 backend behind ``pip install .`` (pyproject.toml; decision D66).

Configures and builds talkhead with CMake (Release; the Python module on, tests and benchmarks off; the
Python the wheel is for: the interpreter running pip), installs it into a scratch prefix as the Debian
package does (everything but the default face, which is made on first use in ~/.cache/talkhead), and packs
that prefix into a wheel for this interpreter:

  talkhead/                      the Python package and its native module (``_talkhead``)
  talkhead-V.data/scripts/       the ``talkhead`` command (→ <venv>/bin)
  talkhead-V.data/data/share/    the data (→ <venv>/share/talkhead: schemes, phonetics, AU maps)
  talkhead-V.data/data/lib/      the plugins (→ <venv>/lib/talkhead: libav, OpenImageIO, dlib)

Settings (``pip install . --config-settings build-dir=DIR`` or the environment variable TALKHEAD_BUILD_DIR): the build
folder (default ``build-pip`` in the source tree, kept between installs so a second one only rebuilds
what changed). A folder that is already configured is built as it is configured (it must have the Python
module on, for this interpreter's version). Uses only the standard library: nothing to download.
"""
import base64
import csv
import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile
from pathlib import Path

NAME = "talkhead"
SUMMARY = "Expressive talking-head videos from timed speech (image-based, Costa 2015)"
SOURCE = Path(__file__).resolve().parents[2]


def _version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    m = re.search(r"project\(talkhead VERSION ([0-9.]+)", text)
    if not m:
        raise RuntimeError("CMakeLists.txt: no 'project(talkhead VERSION …)'")
    return m.group(1)


def _tag():
    py = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{py}-{py}{sys.abiflags}-{platform}"


def _metadata(version):
    return (
        "Metadata-Version: 2.1\n"
        f"Name: {NAME}\n"
        f"Version: {version}\n"
        f"Summary: {SUMMARY}\n"
        "License: GPL-3.0-or-later\n"
        "Requires-Python: >=3.9\n"
        "Requires-Dist: numpy\n"
        "Description-Content-Type: text/markdown\n"
        "\n"
        "talkhead renders videos of a talking face from a timed phonetic transcript, an emotion and speech audio\n"
        "(or from text, with espeak-ng). The Python package runs talkhead's commands in process: see the\n"
        "README's 'From Python' section.\n"
    )


def _run(cmd):
    print("talkhead build:", " ".join(str(c) for c in cmd), file=sys.stderr, flush=True)
    subprocess.run([str(c) for c in cmd], check=True, cwd=SOURCE)


def _cache(build):
    values = {}
    for line in (build / "CMakeCache.txt").read_text(errors="replace").splitlines():
        m = re.match(r"([A-Za-z0-9_]+):[A-Z]+=(.*)", line)
        if m:
            values[m.group(1)] = m.group(2)
    return values


def _build(config_settings):
    settings = config_settings or {}
    build = Path(settings.get("build-dir") or os.environ.get("TALKHEAD_BUILD_DIR") or SOURCE / "build-pip")
    if not build.is_absolute():
        build = SOURCE / build
    if not (build / "CMakeCache.txt").is_file():
        generator = ["-G", "Ninja"] if shutil.which("ninja") else []
        _run(["cmake", "-S", SOURCE, "-B", build, *generator, "-DCMAKE_BUILD_TYPE=Release", "-DTALKHEAD_BUILD_TESTS=OFF",
              "-DTALKHEAD_BUILD_BENCH=OFF", "-DTALKHEAD_PYTHON=ON", f"-DPython3_EXECUTABLE={sys.executable}"])
    cache = _cache(build)
    # A wheel runs on every x86-64-v3 machine (D74): not from a build made for its own machine.
    if cache.get("TALKHEAD_MARCH", "") != "x86-64-v3":
        raise RuntimeError(f"{build}: configured with TALKHEAD_MARCH={cache.get('TALKHEAD_MARCH')!r}: a wheel is made from the "
                           "portable build only (the default, x86-64-v3): use another build-dir")
    if cache.get("TALKHEAD_PYTHON", "OFF").upper() not in ("ON", "TRUE", "1"):
        raise RuntimeError(f"{build}: configured without the Python module (TALKHEAD_PYTHON=OFF): use another build-dir")
    want = f"python{sys.version_info.major}.{sys.version_info.minor}"
    if want not in cache.get("TALKHEAD_PYTHON_INSTALL_DIR", ""):
        raise RuntimeError(f"{build}: configured for another Python ({cache.get('TALKHEAD_PYTHON_INSTALL_DIR')}), not {want}: use another build-dir")
    _run(["cmake", "--build", build, "-j", str(os.cpu_count() or 2)])
    return build


def _files(stage):
    """(path in the wheel, file on disk) for everything the wheel carries."""
    version = _version()
    data = f"{NAME}-{version}.data"
    out = []
    pythons = sorted(stage.glob("lib/python3*/*-packages/talkhead"))
    if len(pythons) != 1:
        raise RuntimeError(f"the install has {len(pythons)} talkhead Python packages")
    for f in sorted(pythons[0].rglob("*")):
        if f.is_file() and "__pycache__" not in f.parts:
            out.append((f"talkhead/{f.relative_to(pythons[0]).as_posix()}", f))
    out.append((f"{data}/scripts/talkhead", stage / "bin" / "talkhead"))
    for f in sorted((stage / "lib" / "talkhead").glob("*.so")):
        out.append((f"{data}/data/lib/talkhead/{f.name}", f))
    for f in sorted((stage / "share" / "talkhead").rglob("*")):
        if f.is_file():
            out.append((f"{data}/data/share/talkhead/{f.relative_to(stage / 'share' / 'talkhead').as_posix()}", f))
    return out


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return [name, f"sha256={digest}", str(len(data))]


def get_requires_for_build_wheel(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    info = Path(metadata_directory) / f"{NAME}-{_version()}.dist-info"
    info.mkdir(parents=True, exist_ok=True)
    (info / "METADATA").write_text(_metadata(_version()))
    return info.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    version = _version()
    build = _build(config_settings)
    with tempfile.TemporaryDirectory(prefix="talkhead-wheel-") as tmp:
        stage = Path(tmp) / "prefix"
        # Everything but the default face (component default_face), as the Debian package (D64).
        _run(["cmake", "--install", build, "--prefix", stage, "--component", "Unspecified", "--strip"])
        # Nothing above the x86-64-v3 floor in what the wheel carries (as cpack checks the Debian package).
        _run(["bash", SOURCE / "scripts" / "check-isa", stage])
        files = _files(stage)
        info = f"{NAME}-{version}.dist-info"
        name = f"{NAME}-{version}-{_tag()}.whl"
        path = Path(wheel_directory) / name
        record = []
        with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as whl:
            def add(arcname, data, mode=0o644):
                zi = zipfile.ZipInfo(arcname, date_time=(2026, 1, 1, 0, 0, 0))
                zi.external_attr = (0o100000 | mode) << 16
                zi.compress_type = zipfile.ZIP_DEFLATED
                whl.writestr(zi, data)
                record.append(_record_line(arcname, data))

            for arcname, f in files:
                add(arcname, f.read_bytes(), 0o755 if os.access(f, os.X_OK) else 0o644)
            add(f"{info}/METADATA", _metadata(version).encode())
            add(f"{info}/WHEEL", f"Wheel-Version: 1.0\nGenerator: talkhead build_backend\nRoot-Is-Purelib: false\nTag: {_tag()}\n".encode())
            add(f"{info}/LICENSE", (SOURCE / "LICENSE").read_bytes())
            add(f"{info}/NOTICE", (SOURCE / "NOTICE").read_bytes())
            text = io.StringIO()
            writer = csv.writer(text, lineterminator="\n")
            writer.writerows(record + [[f"{info}/RECORD", "", ""]])
            zi = zipfile.ZipInfo(f"{info}/RECORD", date_time=(2026, 1, 1, 0, 0, 0))
            zi.external_attr = (0o100000 | 0o644) << 16
            whl.writestr(zi, text.getvalue())
    return name
