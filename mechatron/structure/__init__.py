"""Structure of mechanisms [Egorov, chapter 3]: pair classes, mobility formulas, loops and redundancy, structural
groups, synthesis, and the structural report of a model."""
