// From OpenModelica testsuite/simulation/modelica/events/ServerWithQueue.mos (loadString content)
// name:     ServerWithQueueT3
// keywords: when
// status: correct
//
// Conditional Equations with when-Equations
//
model ServerWithQueueT3
  // EventPortInput inCustomer;
  parameter Real serveTime=0.4 "Time needed to service a customer";
  discrete Integer nrOfArrivedCustomers;
  discrete Integer nrOfServedCustomers;
  discrete Integer nrOfCustomersInQueue(start=0);
  discrete Boolean readyCustomer(start=false);
  discrete Boolean serveCustomer(start=false);

  Real recentServeStart "Most recent start servicing";
  //Boolean tmp(start=false);
  Boolean inCustomer_signal(start=false);

equation
  inCustomer_signal = sample(0,1);

  when inCustomer_signal then // Event: New customer arrives inCustomer.signal
    nrOfArrivedCustomers = pre(nrOfArrivedCustomers)+1;
  end when;

  when readyCustomer then // Event: Customer finished service
    nrOfServedCustomers = pre(nrOfServedCustomers)+1;
  end when;

  when (pre(nrOfCustomersInQueue)==0 and inCustomer_signal) or
       (pre(nrOfCustomersInQueue)>=1 and pre(readyCustomer)) then
    serveCustomer = true;
    recentServeStart = time;
end when;
  //readyCustomer = if (serveCustomer and (serveTime < time-recentServeStart)) then true else false; // works equal
  readyCustomer = serveCustomer and (serveTime < time-recentServeStart); // works equal
  //tmp = serveTime < time-recentServeStart; // works equal
  //readyCustomer = serveCustomer and tmp;   //
  nrOfCustomersInQueue = nrOfArrivedCustomers-nrOfServedCustomers;
end ServerWithQueueT3;
