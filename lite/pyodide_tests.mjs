// The library's browser-safe tests, run inside Pyodide under Node: the same Python, compiled to
// WebAssembly, that a JupyterLite site runs in a browser.
//
//   node lite/pyodide_tests.mjs WHEELS_DIR TESTS_DIR NOTEBOOKS_DIR -- PYTEST_ARGS...
//
// Pyodide's core comes from the npm package pinned in lite/package.json; every wheel in WHEELS_DIR (the
// library's own and the pure-Python wheels it and pytest need, collected by lite/wheels.py) is unpacked
// into Pyodide's site-packages, and nothing is fetched from the network.  TESTS_DIR and NOTEBOOKS_DIR are
// mounted at /project/tests and /project/notebooks, where the tests find the worked solutions
// (notebooks/solutions) as they do in a clone.  Exits with pytest's status.
import { readdirSync, readFileSync } from "node:fs";
import { join, resolve } from "node:path";
import { loadPyodide } from "pyodide";

const [wheels, tests, notebooks, dashdash, ...pytestArgs] = process.argv.slice(2);
if (!wheels || !tests || !notebooks || dashdash !== "--") {
  console.error("usage: node lite/pyodide_tests.mjs WHEELS_DIR TESTS_DIR NOTEBOOKS_DIR -- PYTEST_ARGS...");
  process.exit(2);
}

const pyodide = await loadPyodide();
const write = (stream) => ({ write: (bytes) => { stream.write(bytes); return bytes.length; } });
pyodide.setStdout(write(process.stdout));
pyodide.setStderr(write(process.stderr));
const sitePackages = pyodide.runPython("import site; site.getsitepackages()[0]");
for (const name of readdirSync(wheels).filter((n) => n.endsWith(".whl")).sort()) {
  pyodide.unpackArchive(new Uint8Array(readFileSync(join(wheels, name))), "wheel", { extractDir: sitePackages });
}
pyodide.FS.mkdirTree("/project/tests");
pyodide.FS.mkdirTree("/project/notebooks");
pyodide.FS.mount(pyodide.FS.filesystems.NODEFS, { root: resolve(tests) }, "/project/tests");
pyodide.FS.mount(pyodide.FS.filesystems.NODEFS, { root: resolve(notebooks) }, "/project/notebooks");
pyodide.globals.set("pytest_args", pyodide.toPy(pytestArgs));
const status = await pyodide.runPythonAsync(`
import os, sys
os.chdir("/project")
import modbus_edu
print(f"Pyodide {sys.version.split()[0]} on {sys.platform}: modbus_edu {modbus_edu.__version__} from {modbus_edu.__file__}")
assert modbus_edu.platform.IN_BROWSER
from hypothesis import settings
# WebAssembly is slower than CPython and shares the machine: fewer examples, and no per-example deadline
settings.register_profile("pyodide", max_examples=25, deadline=None)
settings.load_profile("pyodide")
# A build exercise gives a learner's function 2 s for all its inputs, a budget for one laptop; this
# run shares a loaded machine with WebAssembly's slower Python: the registered exercises get 10 s.  The
# time limit's own tests register exercises of their own, with the library's 2 s.
from modbus_edu import exercises
for item in exercises.EXERCISES.values():
    if item.kind == "build":
        item.checker.time_limit *= 5
import pytest
int(pytest.main(["-p", "no:cacheprovider", *pytest_args]))
`);
process.exit(status);
