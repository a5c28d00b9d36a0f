"""A page people read: a self-contained HTML sample of a dataset folder (seed, clean control and the 15
variants of each task side by side, what each pattern inserted highlighted, filters by pattern, level and task
type, a task search).

    from talkdem.dataset_page import load_page_tasks, sample_tasks, write_sample_page
    tasks = load_page_tasks(Path("data"))
    write_sample_page(sample_tasks(tasks, per_type=5), len(tasks), Path("data/sample.html"))
"""

from talkdem.dataset_page.records import PageTask, PageVariant, load_page_tasks, sample_tasks
from talkdem.dataset_page.render import render_sample_page, write_sample_page

__all__ = [
    "PageTask",
    "PageVariant",
    "load_page_tasks",
    "render_sample_page",
    "sample_tasks",
    "write_sample_page",
]
