#!/usr/bin/env bash
# The README's test command: installs what the tests need, runs `cargo test --release`, then builds
# the Python module (python/, pyproject.toml) into the tests' environment and runs its tests with
# pytest (tests/python/: the module, docs/python.md's snippets, examples/calibrate.py). Both run;
# the script fails when either fails.
#
#   scripts/test.sh                           everything: cargo test, then the Python module's tests
#   scripts/test.sh [CARGO TEST ARGS...]      only cargo test, e.g. scripts/test.sh --test runner_interop
#   scripts/test.sh --python [PYTEST ARGS...] only the Python module: build, install, pytest
#
# What the tests need beyond Rust, and where it comes from:
#   - Python packages (tests/requirements.txt: h5py and numpy for the HDF5 interop test, Playwright
#     for the report's browser test) go into a private virtual environment, $CARGO_TARGET_DIR/pyenv
#     (default target/pyenv), made from the system's Python: $DEMSWEEP_BASE_PYTHON, else
#     /usr/bin/python3 (Debian's; not a pyenv or conda shim), else python3 on the PATH. The
#     system's Python is never changed. The tests run $DEMSWEEP_PYTHON, which this script sets
#     to the environment's python.
#   - Debian packages via apt-get, when running as root: chromium (the browser the report test
#     drives; Playwright downloads none), python3-venv (when the base Python lacks venv/ensurepip),
#     slurm-wlm and munge (tests/slurm_cluster.rs starts a throw-away cluster, which needs root),
#     lammps (tests/export_formats.rs reads an exported data file with LAMMPS itself).
# Anything that cannot be installed here is listed in ONE message before any test runs, with how
# to get it, and the script exits 1 without running the tests.
# Repeated runs install nothing: the environment is rebuilt only when tests/requirements.txt changes.
set -euo pipefail
cd "$(dirname "$0")/.."

readonly TARGET=$(realpath -m "${CARGO_TARGET_DIR:-target}")
readonly VENV=$TARGET/pyenv
readonly REQUIREMENTS=tests/requirements.txt

base_python() {
    if [[ -n ${DEMSWEEP_BASE_PYTHON:-} ]]; then
        echo "$DEMSWEEP_BASE_PYTHON"
    elif [[ -x /usr/bin/python3 ]]; then
        echo /usr/bin/python3
    else
        command -v python3 || true
    fi
}
readonly PYTHON=$(base_python)

is_root() { [[ $EUID -eq 0 ]]; }
have_apt() { command -v apt-get >/dev/null; }
have_chromium() { command -v chromium >/dev/null || command -v chromium-browser >/dev/null; }
have_venv() { [[ -n $PYTHON ]] && "$PYTHON" -c 'import venv, ensurepip' 2>/dev/null; }
have_slurm() {
    PATH=$PATH:/usr/sbin:/sbin command -v slurmctld >/dev/null && PATH=$PATH:/usr/sbin:/sbin command -v munged >/dev/null
}
slurm_skipped() { [[ ${DEMSWEEP_ALLOW_NO_SLURM:-} == 1 ]]; }

# Debian packages to install, and what cannot be had here (one line each, with how to get it).
apt_packages=()
missing=()
need_package() {   # PACKAGE... WHY
    local why=${*: -1}
    local packages=("${@:1:$#-1}")
    if is_root && have_apt; then
        apt_packages+=("${packages[@]}")
    else
        missing+=("$why: as root, apt-get install ${packages[*]}")
    fi
}

if [[ -z $PYTHON ]]; then
    missing+=("no Python 3 found (the tests' h5py and Playwright run in a virtual environment made from it): install python3, or set DEMSWEEP_BASE_PYTHON")
elif ! "$PYTHON" -c '' 2>/dev/null; then
    missing+=("$PYTHON (the base Python) does not run: install python3, or set DEMSWEEP_BASE_PYTHON to one")
elif ! have_venv; then
    need_package python3-venv "$PYTHON cannot make a virtual environment (no venv/ensurepip)"
fi
have_chromium || need_package chromium "no Chromium for the report's browser test (tests/report_browser.rs)"
have_lammps() { command -v lmp >/dev/null || command -v lmp_serial >/dev/null; }
have_lammps || need_package lammps "no LAMMPS for the LAMMPS export's test (tests/export_formats.rs)"
if ! slurm_skipped; then
    if ! is_root; then
        missing+=("tests/slurm_cluster.rs starts a throw-away Slurm cluster, which needs root: run as root, or set DEMSWEEP_ALLOW_NO_SLURM=1 to skip that test knowingly")
    elif ! have_slurm; then
        need_package slurm-wlm munge "no Slurm daemons for tests/slurm_cluster.rs"
    fi
fi

if ((${#missing[@]})); then
    {
        echo "scripts/test.sh: the tests need what this machine lacks and this script cannot install:"
        printf '  - %s\n' "${missing[@]}"
        echo "No test was run."
    } >&2
    exit 1
fi

if ((${#apt_packages[@]})); then
    echo "scripts/test.sh: apt-get install ${apt_packages[*]}"
    log=$(mktemp /tmp/demsweep-test-apt.XXXXXX.log)
    if ! { DEBIAN_FRONTEND=noninteractive apt-get update -q \
           && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
                  -o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold "${apt_packages[@]}"; } \
           >"$log" 2>&1; then
        tail -n 20 "$log" >&2
        echo "scripts/test.sh: apt-get install ${apt_packages[*]} failed (log: $log); no test was run" >&2
        exit 1
    fi
    rm -f "$log"
fi

if ! cmp -s "$REQUIREMENTS" "$VENV/requirements.txt"; then
    echo "scripts/test.sh: Python environment $VENV from $PYTHON:" $(grep -o '^[A-Za-z0-9_.-]*' "$REQUIREMENTS")
    rm -rf "$VENV"
    "$PYTHON" -m venv "$VENV"
    if ! "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check -r "$REQUIREMENTS"; then
        echo "scripts/test.sh: pip could not install $REQUIREMENTS into $VENV (is PyPI reachable?); no test was run" >&2
        exit 1
    fi
    cp "$REQUIREMENTS" "$VENV/requirements.txt"
fi

export DEMSWEEP_PYTHON=$VENV/bin/python

# The Python module, built against the same build folder (the library's dependencies compile once)
# with the environment's maturin, and installed into the environment; its tests run the module and
# the `demsweep` command of the same build ($DEMSWEEP_BIN).
python_tests() {
    local started=$SECONDS
    # PYO3_PYTHON: the base Python, as .ci/run's clippy uses (the same one: PyO3 is not rebuilt).
    if ! PATH=$VENV/bin:$PATH PYO3_PYTHON=$PYTHON CARGO_TARGET_DIR=$TARGET \
         "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-build-isolation --no-deps \
         --force-reinstall . ; then
        echo "scripts/test.sh: the Python module did not build (pip install . above); its tests were not run" >&2
        return 1
    fi
    cargo build --release --quiet --bin demsweep || return 1
    echo "scripts/test.sh: Python module built and installed in $((SECONDS - started)) s; pytest tests/python"
    local status=0
    DEMSWEEP_BIN=$TARGET/release/demsweep "$VENV/bin/python" -m pytest -q tests/python "$@" || status=$?
    # pytest: 0 passed, 1 some failed, 2 interrupted, 3 internal error, 4 usage error, 5 no tests ran.
    case $status in
        0) ;;
        5) echo "scripts/test.sh: pytest found no Python tests to run" >&2 ;;
        *) echo "scripts/test.sh: the Python tests failed (pytest exit status $status)" >&2 ;;
    esac
    echo "scripts/test.sh: Python module and tests took $((SECONDS - started)) s"
    return $((status != 0))
}

if [[ ${1:-} == --python ]]; then
    shift
    python_tests "$@"
    exit
fi
if (($#)); then
    echo "scripts/test.sh: cargo test $*; the Python module's tests run without arguments, or with --python"
    exec cargo test --release --no-fail-fast "$@"
fi
cargo_status=0
cargo test --release --no-fail-fast || cargo_status=$?
python_status=0
python_tests || python_status=$?
if ((cargo_status || python_status)); then
    echo "scripts/test.sh: failed:$( ((cargo_status)) && echo " cargo test (exit status $cargo_status)")$( ((python_status)) && echo " the Python module's tests")" >&2
    exit 1
fi
