"""Scoring helpers the backends build on: the token trie, branch and bound, the prefix-cached scorer (torch), the
served scoring protocol and the result cache. Imported by module, so importing this package loads no library."""
