// From OpenModelica testsuite/simulation/modelica/indexreduction/reinit.mos (loadString content)
// Name:     reinit
// keywords: index reduction, reinit, state selection
// status:   correct
model SelectReinit
  Real x(start = 1, fixed = true);
  Real y;
equation
  der(y) = -y;
  y = x;
  when time > 0.5 then
    reinit(x, 1);
  end when;
end SelectReinit;
