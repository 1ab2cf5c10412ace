"""The package's modules in layers: each imports only modules of the layers before it (so a
value's path through a fit goes forward, never back into a module it left), at the top of the
module (an import inside a function hides a circle), and the only private names one module
takes from another are the helpers module's."""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "splinegpu"

# The order a fit runs in: arguments, surfaces, meshes, queries and the context first, the
# B-spline arithmetic, the piecewise polynomials (power, then Bernstein) and the cubic fits on
# them, B-splines and their fits, FITPACK's doors, the gridded splines, the batches, and the
# public namespaces last.
LAYERS = ["_native", "_helpers", "_surfaces", "_geometry", "_queries", "_context", "_bspl",
          "_collocation", "_ppoly", "_bpoly", "_cubic", "_bsplines", "_lsq", "_smoothing",
          "_fitpack_repro", "_fitpack_py", "_ndbspline", "_fitpack2", "_rgi", "_interp1d",
          "_batches", "interpolate", "__init__", "dask"]


def imports(path: Path):
    """(module, names, inside a function) of each import of a sibling module in `path`."""
    tree = ast.parse(path.read_text())
    nested = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef,
                                                               ast.AsyncFunctionDef))
              for n in ast.walk(f) if n is not f}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module is None:
                for alias in node.names:
                    yield alias.name, [], id(node) in nested
            else:
                yield node.module, [a.name for a in node.names], id(node) in nested
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("splinegpu"):
            yield node.module.removeprefix("splinegpu").lstrip(".") or "__init__", \
                [a.name for a in node.names], id(node) in nested
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "splinegpu":
                    name = alias.name.removeprefix("splinegpu").lstrip(".") or "__init__"
                    yield name, [], id(node) in nested


def test_every_module_has_a_layer():
    modules = {p.stem for p in PACKAGE.glob("*.py")}
    assert modules == set(LAYERS) - {"_native"}


def test_modules_import_only_earlier_layers_at_their_top():
    broken = []
    for path in sorted(PACKAGE.glob("*.py")):
        layer = LAYERS.index(path.stem)
        for module, _, inside in imports(path):
            if LAYERS.index(module) >= layer:
                broken.append(f"{path.name} imports {module}, a later layer")
            if inside:
                broken.append(f"{path.name} imports {module} inside a function")
    assert not broken, broken


def test_private_names_come_only_from_the_helpers_module():
    taken = [f"{path.name} takes {name} from {module}"
             for path in sorted(PACKAGE.glob("*.py"))
             for module, names, _ in imports(path) if module != "_helpers"
             for name in names if name.startswith("_") and name != "_native"]
    assert not taken, taken
