"""Reporting: the result protocol every analysis follows, JSON-ready data, figures and progress bars."""
