"""The project store: one SQLite file per project (the scene document, takes, the journal
of the take being recorded), checksummed, salvageable, recoverable after a crash, and
locked to one studio at a time."""
