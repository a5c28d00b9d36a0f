"""What a build reports rather than builds: the LLM path's attempt statistics and costs for the dataset card
(`llm_stats`) and the measured LLM sample behind them (`llm_sample`).

Kept out of `builders.generation` so that generators never import the build pipeline they feed.
"""
