"""Reading and writing files (CSV, JSON, YAML, Parquet); validation errors are InputError."""
