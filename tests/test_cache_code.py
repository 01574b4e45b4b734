"""A cached summary is keyed on vlab's code as well as its version number: a summary written by
other code (a field added, a measurement changed, the version number not bumped) is not served."""

import shutil

from vlab import __version__
from vlab.study.cache import cache_key, code_fingerprint, fingerprint


def test_the_fingerprint_changes_with_one_byte_of_a_module_and_not_with_bytecode(tmp_path):
    package = tmp_path / "vlab"
    (package / "sub").mkdir(parents=True)
    (package / "a.py").write_text("x = 1\n")
    (package / "sub" / "b.toml").write_text("k = 2\n")
    before = fingerprint(package)
    (package / "sub" / "__pycache__").mkdir()
    (package / "sub" / "__pycache__" / "b.cpython-311.pyc").write_bytes(b"\x00" * 8)
    (package / "notes.txt").write_text("not code")
    assert fingerprint(package) == before
    (package / "a.py").write_text("x = 2\n")
    assert fingerprint(package) != before
    (package / "a.py").write_text("x = 1\n")
    shutil.move(package / "sub" / "b.toml", package / "b.toml")  # same bytes, another module path
    assert fingerprint(package) != before


def test_the_key_depends_on_the_code_and_the_default_is_this_process_s_code():
    base = cache_key("scene", {"k": 1}, __version__, {}, code="a" * 64)
    assert cache_key("scene", {"k": 1}, __version__, {}, code="b" * 64) != base
    assert cache_key("scene", {"k": 1}, __version__, {}, code="a" * 64) == base
    assert cache_key("scene", {"k": 1}) == cache_key("scene", {"k": 1}, code=code_fingerprint())
    assert len(code_fingerprint()) == 64

