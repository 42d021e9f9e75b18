"""Drive sizing: transmission ratios [Egorov, section 4.4], catalogs, motor and converter selection with the checks
vendor tools run (:func:`mechatron.size`), and the results they return."""
