"""The LLM interface: `LanguageModel` and its requests, the options a backend declares, the backend registry and
the model catalogue. Light: nothing here imports a backend's library."""
