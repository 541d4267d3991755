% Michalski's east/west trains (after Michalski 1980), written for planerel's tests.
% Ten trains; every eastbound train has a short closed car, no westbound train has one.

:- set(clauselength, 4).
:- set(i, 2).

:- modeh(1, eastbound(+train)).
:- modeb(*, has_car(+train, -car)).
:- modeb(1, short(+car)).
:- modeb(1, long(+car)).
:- modeb(1, closed(+car)).
:- modeb(1, open_car(+car)).
:- modeb(1, shape(+car, #shape)).
:- modeb(1, wheels(+car, #int)).
:- modeb(1, load(+car, #shape, #int)).

:- determination(eastbound/1, has_car/2).
:- determination(eastbound/1, short/1).
:- determination(eastbound/1, long/1).
:- determination(eastbound/1, closed/1).
:- determination(eastbound/1, open_car/1).
:- determination(eastbound/1, shape/2).
:- determination(eastbound/1, wheels/2).
:- determination(eastbound/1, load/3).

% types
train(east1).
train(east2).
train(east3).
train(east4).
train(east5).
train(west6).
train(west7).
train(west8).
train(west9).
train(west10).
car(car_11).
car(car_12).
car(car_13).
car(car_14).
car(car_21).
car(car_22).
car(car_23).
car(car_31).
car(car_32).
car(car_33).
car(car_41).
car(car_42).
car(car_43).
car(car_44).
car(car_51).
car(car_52).
car(car_53).
car(car_61).
car(car_62).
car(car_71).
car(car_72).
car(car_73).
car(car_81).
car(car_82).
car(car_91).
car(car_92).
car(car_93).
car(car_94).
car(car_101).
car(car_102).
shape(bucket).
shape(circle).
shape(diamond).
shape(ellipse).
shape(hexagon).
shape(rectangle).
shape(square).
shape(triangle).
shape(u_shaped).
int(1). int(2). int(3).

% trains
has_car(east1, car_11).
long(car_11).
open_car(car_11).
shape(car_11, rectangle).
wheels(car_11, 2).
load(car_11, square, 3).
has_car(east1, car_12).
short(car_12).
closed(car_12).
shape(car_12, rectangle).
wheels(car_12, 2).
load(car_12, triangle, 1).
has_car(east1, car_13).
long(car_13).
open_car(car_13).
shape(car_13, rectangle).
wheels(car_13, 3).
load(car_13, hexagon, 1).
has_car(east1, car_14).
short(car_14).
open_car(car_14).
shape(car_14, rectangle).
wheels(car_14, 2).
load(car_14, circle, 1).
has_car(east2, car_21).
short(car_21).
open_car(car_21).
shape(car_21, u_shaped).
wheels(car_21, 2).
load(car_21, triangle, 1).
has_car(east2, car_22).
short(car_22).
open_car(car_22).
shape(car_22, bucket).
wheels(car_22, 2).
load(car_22, rectangle, 1).
has_car(east2, car_23).
short(car_23).
closed(car_23).
shape(car_23, rectangle).
wheels(car_23, 2).
load(car_23, circle, 2).
has_car(east3, car_31).
short(car_31).
open_car(car_31).
shape(car_31, u_shaped).
wheels(car_31, 2).
load(car_31, triangle, 1).
has_car(east3, car_32).
long(car_32).
closed(car_32).
shape(car_32, rectangle).
wheels(car_32, 3).
load(car_32, triangle, 1).
has_car(east3, car_33).
short(car_33).
closed(car_33).
shape(car_33, rectangle).
wheels(car_33, 2).
load(car_33, circle, 1).
has_car(east4, car_41).
short(car_41).
open_car(car_41).
shape(car_41, rectangle).
wheels(car_41, 2).
load(car_41, rectangle, 1).
has_car(east4, car_42).
short(car_42).
closed(car_42).
shape(car_42, ellipse).
wheels(car_42, 2).
load(car_42, diamond, 1).
has_car(east4, car_43).
short(car_43).
open_car(car_43).
shape(car_43, u_shaped).
wheels(car_43, 2).
load(car_43, triangle, 1).
has_car(east4, car_44).
short(car_44).
open_car(car_44).
shape(car_44, bucket).
wheels(car_44, 2).
load(car_44, triangle, 1).
has_car(east5, car_51).
short(car_51).
open_car(car_51).
shape(car_51, bucket).
wheels(car_51, 2).
load(car_51, triangle, 1).
has_car(east5, car_52).
long(car_52).
open_car(car_52).
shape(car_52, rectangle).
wheels(car_52, 2).
load(car_52, rectangle, 1).
has_car(east5, car_53).
short(car_53).
closed(car_53).
shape(car_53, rectangle).
wheels(car_53, 2).
load(car_53, triangle, 1).
has_car(west6, car_61).
long(car_61).
closed(car_61).
shape(car_61, rectangle).
wheels(car_61, 2).
load(car_61, circle, 3).
has_car(west6, car_62).
short(car_62).
open_car(car_62).
shape(car_62, rectangle).
wheels(car_62, 2).
load(car_62, triangle, 1).
has_car(west7, car_71).
long(car_71).
open_car(car_71).
shape(car_71, rectangle).
wheels(car_71, 3).
load(car_71, hexagon, 1).
has_car(west7, car_72).
short(car_72).
open_car(car_72).
shape(car_72, u_shaped).
wheels(car_72, 2).
load(car_72, circle, 1).
has_car(west7, car_73).
long(car_73).
closed(car_73).
shape(car_73, rectangle).
wheels(car_73, 2).
load(car_73, rectangle, 1).
has_car(west8, car_81).
long(car_81).
closed(car_81).
shape(car_81, rectangle).
wheels(car_81, 2).
load(car_81, rectangle, 1).
has_car(west8, car_82).
short(car_82).
open_car(car_82).
shape(car_82, u_shaped).
wheels(car_82, 2).
load(car_82, circle, 1).
has_car(west9, car_91).
short(car_91).
open_car(car_91).
shape(car_91, u_shaped).
wheels(car_91, 2).
load(car_91, circle, 1).
has_car(west9, car_92).
long(car_92).
closed(car_92).
shape(car_92, rectangle).
wheels(car_92, 2).
load(car_92, rectangle, 1).
has_car(west9, car_93).
short(car_93).
open_car(car_93).
shape(car_93, rectangle).
wheels(car_93, 2).
load(car_93, circle, 1).
has_car(west9, car_94).
short(car_94).
open_car(car_94).
shape(car_94, u_shaped).
wheels(car_94, 2).
load(car_94, triangle, 1).
has_car(west10, car_101).
long(car_101).
open_car(car_101).
shape(car_101, rectangle).
wheels(car_101, 2).
load(car_101, rectangle, 2).
has_car(west10, car_102).
short(car_102).
open_car(car_102).
shape(car_102, u_shaped).
wheels(car_102, 2).
load(car_102, rectangle, 1).
