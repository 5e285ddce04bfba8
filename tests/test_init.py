"""morph/__init__.py: the names ``import morph`` documents, loaded lazily (PEP 562)."""

import subprocess
import sys

import morph


def test_every_public_name_resolves_to_a_function_of_its_module():
    for name in morph.__all__:
        value = getattr(morph, name)
        if name in ("budget", "errors"):       # submodules
            assert value.__name__ == "morph." + name
            continue
        assert callable(value), name
        assert value.__name__ == name and value.__module__.startswith("morph."), name


def test_plain_import_reaches_the_errors_the_budget_and_the_region_type():
    code = ("import morph; morph.errors.MorphError; morph.budget.plan; "
            "assert issubclass(morph.OperandError, (morph.MorphError, ValueError)); "
            "morph.Region; morph.Shape")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_readme_library_names_are_public():
    # what the README's library section lists: offsets, C-space, brush and
    # stroke fonts, export
    for name in ("minkowski_sum", "offset_region", "cspace_obstacle", "stroke_paths",
                 "brush_font", "stroke_ufo", "ellipse_nib", "loop_to_cubics",
                 "loops_to_beziers", "glyph_region", "svg_region", "write_svg", "write_png"):
        assert name in morph.__all__, name


def test_import_morph_loads_no_submodule_until_asked():
    code = ("import sys, morph; print(sorted(m for m in sys.modules "
            "if m.startswith('morph.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"
