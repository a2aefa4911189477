"""The weight family (issue 8): correction-weight kinds beyond the planar balls
and pendulums of the core simulator -- two-axis pendulums (ch. 6), the
gravity-insensitive coupled pair and the autobalancer-damper (ch. 7), liquid
float (paper 001) and chamber (thesis 002) balancers, friction models."""
