"""The run's CSV tables as pandas DataFrames when pandas is installed, lists of dicts otherwise
(numbers as int or float, the rest as str)."""

import csv
import io

try:
    import pandas as _pd
except ImportError:  # pandas is optional
    _pd = None


def _value(text):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_table(text):
    """A CSV text with a header line as a table."""
    if _pd is not None:
        return _pd.read_csv(io.StringIO(text))
    reader = csv.DictReader(io.StringIO(text))
    return [{k: _value(v) for k, v in row.items()} for row in reader]


def read_table(path):
    """A CSV file of a run (objects.csv, events.csv, tracks.csv, people.csv) as a table."""
    with open(path, newline="") as f:
        return parse_table(f.read())


def table_of_rows(columns, rows):
    """Rows (tuples in `columns` order) as a table."""
    if _pd is not None:
        return _pd.DataFrame(list(rows), columns=list(columns))
    return [dict(zip(columns, row)) for row in rows]
