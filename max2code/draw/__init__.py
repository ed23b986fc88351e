"""Drawing: animated SVG, overview pictures and GIFs of a simulation trace."""
