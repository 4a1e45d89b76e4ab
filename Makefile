# proxemic — every target sets itself up on a fresh machine (Debian packages, virtual env,
# pip installs, the maturin release build). `make help` lists the targets.

SHELL := /bin/bash
VENV ?= .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
OUT ?= out
export MUJOCO_GL ?= egl
# The Rust targets share one target dir; release everywhere so tests reuse the build.
CARGO_FLAGS := --workspace --release

.DEFAULT_GOAL := help
.PHONY: help setup system-deps build demo test test-full test-rust test-python wheel install-check lint format docs bench soak fuzz clean

help: ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F ':.*## ' '{printf "  make %-12s %s\n", $$1, $$2}'

system-deps: ## Debian packages for offscreen rendering (EGL and OSMesa), if missing
	@pkgs="libegl1 libegl-mesa0 libgl1-mesa-dri libopengl0 libosmesa6 libglfw3"; \
	if dpkg -s $$pkgs >/dev/null 2>&1; then echo "system packages present"; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "installing $$pkgs"; apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$pkgs >/dev/null; \
	else echo "warning: cannot install $$pkgs (not root or no apt-get); rgb_array rendering may be unavailable"; fi

$(VENV)/.deps: pyproject.toml Makefile
	@test -x $(PY) || python3 -m venv $(VENV)
	$(PIP) install -q --upgrade pip
	$(PIP) install -q maturin "numpy>=1.26" "gymnasium>=1.0" "mujoco>=3.3" "matplotlib>=3.7" "tqdm>=4.60" "pyarrow>=14" \
	    "pytest>=8" "ruff>=0.6" "mypy>=1.10" "imageio>=2.30" "imageio-ffmpeg>=0.5" "pettingzoo>=1.24" "supersuit>=3.9"
	$(PIP) install -q "ray>=2.9"  # the `ray` extra: the Ray backend of eval and tune is tested too
	@touch $@

# The `rl` extra (stable-baselines3 and torch: about 5.4 GB with torch's CUDA libraries, the only
# torch build PyPI has for Linux; docs/training.md): only `make test` and the training example need it.
# pip needs the wheels and the installed files at once: about 8 GB free, checked first so a full
# disk says so instead of failing half-way through torch's install.
RL_FREE_GB := 8
$(VENV)/.rl-deps: $(VENV)/.deps
	@free=$$(df -Pk $(VENV) | awk 'NR==2 {print int($$4 / 1048576)}'); \
	if [ "$$free" -lt $(RL_FREE_GB) ]; then \
	  echo "error: the rl extra (stable-baselines3, torch) needs about $(RL_FREE_GB) GB free on the disk of $(VENV); $$free GB are free" >&2; exit 1; fi
	$(PIP) install -q "stable-baselines3>=2.3"
	@touch $@

$(VENV)/.docs-deps: Makefile
	@test -x $(PY) || python3 -m venv $(VENV)
	$(PIP) install -q "mkdocs>=1.6" "mkdocs-material>=9.5" "mkdocstrings[python]>=0.26"
	@touch $@

build: $(VENV)/.deps ## compile the Rust core and install the package into the venv (maturin, release)
	@. $(VENV)/bin/activate && maturin develop --release --quiet 2>&1 | grep -v "^📦\|^🔗\|^🐍" || true
	@$(PY) -c "import proxemic; print('proxemic', proxemic.__version__, 'built')"

setup: system-deps build ## everything needed to run the demo and the tests

demo: setup ## the baselines vs the social planners in the museum and the care center on test-split seeds: tables and plots (in out/)
	$(VENV)/bin/proxemic demo --out $(OUT)
	@echo "The proxemic command and the package are in $(VENV): run . $(VENV)/bin/activate, then proxemic --help (or call $(VENV)/bin/proxemic and $(VENV)/bin/python)."

test: setup test-rust test-python ## all Rust and Python tests

test-rust: ## Rust unit and integration tests (property tests with a fixed seed: the same cases every run)
	PROPTEST_RNG_SEED=$${PROPTEST_RNG_SEED:-20261122} cargo test $(CARGO_FLAGS) --quiet

test-python: $(VENV)/.rl-deps ## Python tests (gymnasium conformance, determinism, errors, install, PPO learning)
	PROXEMIC_REQUIRE_RL=1 $(PY) -m pytest -q

test-full: setup ## the full claims suites on the whole test split (60 seeds per scene, 60 generated scenes; pytest -m full): social vs the baselines, the yielding claims, the timeout and collision rates; the calibrated people on the ETH recordings; the docs snippets that take minutes; the differential-drive success-rate table regenerated; the generated tables of docs/learned.md and docs/crowdnav.md rerun whole
	$(PY) -m pytest -q -m full tests/test_social_vs_astar.py tests/test_crowd_card.py tests/test_progress.py tests/test_snippets.py \
	    tests/test_differential_drive.py tests/test_baselines.py tests/test_crowdnav.py

# Without zig (not installable here) maturin links against this machine's glibc, so the wheel's tag
# is the lowest manylinux its symbols allow: manylinux_2_35 on Debian 12 (glibc 2.36), as maturin's
# own audit finds. `--auditwheel check` fails the build if the wheel needs a shared library outside
# the manylinux policy (none is bundled or repaired in).
WHEEL_DIR := target/wheels
INSTALL_VENV := /tmp/proxemic-install-check

wheel: $(VENV)/.deps ## an abi3 manylinux wheel (maturin, release) in target/wheels: installs with pip, no Rust toolchain
	rm -f $(WHEEL_DIR)/proxemic-*.whl
	. $(VENV)/bin/activate && maturin build --release --compatibility manylinux_2_35 --auditwheel check --out $(WHEEL_DIR)
	@ls -l $(WHEEL_DIR)/proxemic-*.whl

install-check: system-deps wheel ## the wheel into a fresh venv with no cargo on PATH, then gym.make and parallel_env from /
	rm -rf $(INSTALL_VENV) && python3 -m venv $(INSTALL_VENV)
	cd / && env PATH=$(INSTALL_VENV)/bin:/usr/bin:/bin bash -c '\
	  if command -v cargo || command -v rustc; then echo "install-check: a Rust toolchain is on PATH"; exit 1; fi; \
	  echo "no cargo or rustc on PATH: $$PATH"; \
	  pip install -q $(CURDIR)/$(WHEEL_DIR)/proxemic-*.whl && \
	  python -c "import gymnasium as gym, proxemic; \
	    env = gym.make(\"proxemic/Museum-v5\"); obs, _ = env.reset(seed=0); \
	    print(\"installed proxemic\", proxemic.__version__, \"from the wheel, runs from\", __import__(\"os\").getcwd(), {k: v.shape for k, v in obs.items()}); \
	    penv = proxemic.parallel_env(\"daza2021_fig15\"); pobs, _ = penv.reset(seed=0); \
	    print(\"parallel_env (PettingZoo, a core dependency):\", sorted(pobs))"'

lint: $(VENV)/.deps ## rustfmt, clippy (warnings as errors), ruff, mypy (settings in pyproject.toml)
	cargo fmt --all --check
	cargo clippy --workspace --all-targets -- -D warnings
	$(VENV)/bin/ruff check python tests benches examples
	$(VENV)/bin/ruff format --check python tests benches examples
	$(VENV)/bin/mypy

format: $(VENV)/.deps ## apply rustfmt and ruff format
	cargo fmt --all
	$(VENV)/bin/ruff format python tests benches examples
	$(VENV)/bin/ruff check --fix python tests benches examples

docs: build $(VENV)/.docs-deps ## the documentation site into site/ (MkDocs, warnings as errors), with the Rust core's cargo doc
	$(PY) -m proxemic.reference --check docs
	RUSTDOCFLAGS="-D warnings" cargo doc --no-deps -p proxemic-core --quiet
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --quiet

BENCHES := planning pedestrians proxemics groups socialmap controllers orca world

bench: setup ## criterion benches of the core (medians, checked against their targets), env, parallel env and rendering throughput, ORCA and pedestrians vs navground; fails when a bench crashes or a target is MISSED (every bench still runs)
	mkdir -p target && touch target/bench-start
	set -o pipefail; for b in $(BENCHES); do cargo bench -p proxemic-core --bench $$b -- --warm-up-time 1 --measurement-time 3 \
	  | grep -E '^[a-z_/0-9.]+|time:|thrpt:' || exit 1; done
	status=0; for script in criterion_targets env_bench calderita_bench parallel_bench crowd_bench eval_bench vector_bench orca_vs_navground pedestrians_vs_navground; do \
	  $(PY) benches/$$script.py $$([ $$script = criterion_targets ] && echo --newer-than target/bench-start) || { echo "benches/$$script.py: failed or missed a target"; status=1; }; done; exit $$status

soak: setup ## 1M museum env steps and 200k 4-robot parallel steps, random actions: fails if RSS grows >5% after warm-up or an observation leaves its space
	$(PY) tests/soak.py

FUZZ_SECONDS ?= 600
FUZZ_ARGS ?=
fuzz: ## mutation fuzzer of scenarios, scene names and replay tracks for FUZZ_SECONDS (default 600): fails on any panic or broken record invariant (FUZZ_ARGS=--keep-going runs to the end)
	cargo run --release -p proxemic-core --example fuzz_scenario -- --seconds $(FUZZ_SECONDS) $(FUZZ_ARGS)

clean: ## remove build products and the venv
	rm -rf target $(VENV) $(OUT) site python/proxemic/_core*.so
