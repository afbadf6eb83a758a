"""Every public class, function, method and property of the package has a
docstring, and help() shows it (the manual's promise: `help(tumble.World)`
documents every method)."""

from __future__ import annotations

import inspect
import pydoc

import tumble

DATA = {"__version__", "CONTACT_DTYPE", "INTEGRATORS"}


def public_objects():
    for name in tumble.__all__:
        if name in DATA:
            continue
        yield name, getattr(tumble, name)


def members(cls):
    """Public attributes defined by the class itself (not inherited from object)."""
    for name, value in vars(cls).items():
        if name.startswith("_") or name in DATA:
            continue
        yield name, value


def doc_of(value) -> str:
    if isinstance(value, (classmethod, staticmethod)):
        value = value.__func__
    return inspect.getdoc(value) or ""


def test_every_public_name_has_a_docstring_shown_by_help():
    checked = 0
    for name, obj in public_objects():
        doc = inspect.getdoc(obj)
        assert doc and doc.strip(), f"tumble.{name} has no docstring"
        # help() renders the docstring (its first line, whitespace normalised).
        first = " ".join(doc.strip().splitlines()[0].split())
        shown = " ".join(pydoc.render_doc(obj, renderer=pydoc.plaintext).split())
        assert first in shown, f"help(tumble.{name}) does not show {first!r}"
        checked += 1
    assert checked >= 15


def test_every_public_method_and_property_has_a_docstring():
    missing = []
    checked = 0
    for name, obj in public_objects():
        if not inspect.isclass(obj) or issubclass(obj, BaseException):
            continue
        for member, value in members(obj):
            documented_kinds = (property, classmethod, staticmethod)
            if not (
                callable(value)
                or inspect.isdatadescriptor(value)
                or isinstance(value, documented_kinds)
            ):
                continue
            checked += 1
            if not doc_of(value).strip():
                missing.append(f"tumble.{name}.{member}")
    assert not missing, f"no docstring: {missing}"
    assert checked >= 60, f"only {checked} members checked"


def test_exceptions_say_when_they_are_raised():
    for cls in (
        tumble.TumbleError,
        tumble.InvalidArgument,
        tumble.StaleBodyError,
        tumble.FileError,
        tumble.InternalError,
    ):
        assert (inspect.getdoc(cls) or "").strip(), cls.__name__
