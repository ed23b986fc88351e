"""Reports: figure 6 (table), accuracy, event versus frame and what the
variants buy; each writes tables and plots from measured figures."""
