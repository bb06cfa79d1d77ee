"""The project store: one SQLite file per project (scene document, takes, journal), checked and recoverable."""
