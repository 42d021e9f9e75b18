"""Friction, wear, life and efficiency of kinematic pairs and drives ([Egorov, chapter 7])."""
