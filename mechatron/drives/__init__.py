"""Drive sizing: transmission ratios (textbook section 4.4), catalogs, motor and gearbox selection with the checks
vendor tools run, and reports."""
