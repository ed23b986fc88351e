"""Build hook: the wheel carries the repository's top-level data folders
(paths.DATA_FOLDERS: templates, equations, examples, runtime sources,
conformance cases) as package data under max2code/_data/, with the same
relative layout, so that max2code/paths.py finds them through
importlib.resources wherever the package is installed.  An editable install
(pip install -e .) copies nothing: paths.py reads the checkout itself."""
import fnmatch
import os
import shutil

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))


def _paths_constant(name):
    """A tuple constant of max2code/paths.py, read without importing the package."""
    import ast
    with open(os.path.join(HERE, "max2code", "paths.py"), encoding="utf-8") as fh:
        tree = ast.parse(fh.read())
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == name for t in node.targets):
            return ast.literal_eval(node.value)
    raise RuntimeError(f"max2code/paths.py has no {name}")


class build_py_with_data(build_py):
    def run(self):
        super().run()
        if getattr(self, "editable_mode", False):
            return
        ignored = _paths_constant("IGNORED")

        def ignore(_folder, names):
            return [n for n in names if any(fnmatch.fnmatch(n, pat) for pat in ignored)]

        dest = os.path.join(self.build_lib, "max2code", "_data")
        for folder in _paths_constant("DATA_FOLDERS"):
            src = os.path.join(HERE, folder)
            if not os.path.isdir(src):
                raise RuntimeError(f"{src}: missing (the package carries it as data)")
            out = os.path.join(dest, folder)
            shutil.rmtree(out, ignore_errors=True)
            shutil.copytree(src, out, ignore=ignore)


setup(cmdclass={"build_py": build_py_with_data})
