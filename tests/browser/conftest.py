"""The notebook in this folder is driven by tests/test_browser.py in a real browser; nbval must not run it."""

collect_ignore_glob = ["*.ipynb"]
