// From OpenModelica testsuite/simulation/modelica/events/IntegerZeroCrossings.mos (loadString content)
// name:     IntegerZeroCrossings
// keywords: events, zerossings, integer
// status: correct
// Check for interger valued zerocrossings function
model IntZC
  Integer count(start=0, fixed=true);
equation
  when integer(time/0.1) > pre(count) then
    count = pre(count)+1;
  end when;
end IntZC;
