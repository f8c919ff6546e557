"""Writing a document measures and glues each text once (metro.core.documents.text's caches), with
the results the uncached functions give."""

from __future__ import annotations

from metro.core.documents import text as T


TEXTS = ["U = 1.2 ppm (k = 2)", "0.0006021 °/h", "α = -2.3", "扩展不确定度 Expanded uncertainty",
         "K_l = 3", "(s_upper − Kr)/2", "4.946×10⁻⁸ °/°C/h", "", "run_0.0001.csv"]


def test_glue_cached_gives_what_it_computes():
    T.glue.cache_clear()
    for text in TEXTS * 3:
        assert T.glue(text) == T.glue.__wrapped__(text)
    info = T.glue.cache_info()
    assert info.misses == len(set(TEXTS)) and info.hits == 3 * len(TEXTS) - info.misses


def test_a_table_measured_again_at_a_smaller_size_measures_each_text_once():
    columns = [["参数 parameter", "试验方法 test method", "低温 low temperature"],
               ["数值 value", "GB/T 2423.22", "-55 °C"]]
    T._text_em.cache_clear()
    T._words_of.cache_clear()
    first = T.column_widths(columns, 170.0, 9.0)
    misses = T._text_em.cache_info().misses
    smaller = T.column_widths(columns, 170.0, 8.5)
    assert T._text_em.cache_info().misses == misses  # nothing measured twice
    assert T._words_of.cache_info().misses == len({c for col in columns for c in col})
    # the widths are those of the characters' advances summed, at each size
    cell = columns[0][1]
    assert T.text_mm(cell, 8.5) == sum(T._char_em(c) for c in cell) * 8.5 * 25.4 / 72
    assert first is not None and smaller is not None and abs(sum(first) - 170.0) < 1e-6
