"""The candidates' token trie both exact scorers walk."""

from __future__ import annotations

from talkdem.llm.scoring.token_trie import TokenTrie


def test_trie_shares_common_beginnings() -> None:
    trie = TokenTrie()
    assert trie.add_path([5, 6, 7]) == [0, 1, 2]
    assert trie.new_nodes([5, 6, 8]) == 1 and trie.new_nodes([5, 6, 7]) == 0 and trie.new_nodes([9]) == 1
    assert trie.add_path([5, 6, 8]) == [0, 1, 3]
    assert trie.parents == [-1, 0, 1, 1] and trie.depths == [0, 1, 2, 2]
    assert trie.path(3) == [5, 6, 8] and trie.path(0) == [5]


def test_candidates_mark_where_they_end_and_the_earlier_duplicate_wins() -> None:
    trie = TokenTrie.of([[1, 2], [1], [1, 2], [3]])
    one, two, three = trie.roots[1], trie.children[trie.roots[1]][2], trie.roots[3]
    assert trie.ends[one] == 1 and trie.ends[two] == 0 and trie.ends[three] == 3
    assert sorted(trie.ends) == [0, 1, 3]
