"""The backends behind `LanguageModel` (hf, llamacpp, vllm, openai) and the tokenizing they share
(`tokenizing`, `served_tokenizer`). Each imports its heavy library (torch, llama.cpp, vLLM) only when
constructed; `talkdem.llm.interface.registry` names them by module, so nothing here is imported up front."""
